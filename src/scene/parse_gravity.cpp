// The scene's [gravity] table (issue 30): self-gravity and the equilibrium start
// (shatter/gravity/config.hpp). The uniform field is solver.gravity, read with the solver.

#include <algorithm>

#include <fmt/format.h>

#include "scene/parts.hpp"
#include "shatter/gravity/config.hpp"

namespace shatter::scene {

void read_gravity(Reader& root, Scene& scene) {
  toml::table* t = root.subtable("gravity");
  if (t == nullptr) return;
  Reader r(*t, "gravity", root.where("gravity"));
  r.allow({"self", "mesh", "G", "dt_factor", "equilibrium"});
  r.reject_unknown();
  gravity::GravityConfig& g = scene.solver.self_gravity;
  g.self = r.boolean("self", false);
  r.note_range("mesh",
               fmt::format("[{}, {}]; the FFT mesh is twice this per side",
                           gravity::MeshGravity::kMinCells, gravity::MeshGravity::kMaxCells),
               "nodes per side");
  const auto mesh = r.integer("mesh", g.mesh);
  if (mesh < gravity::MeshGravity::kMinCells || mesh > gravity::MeshGravity::kMaxCells) {
    r.fail("mesh",
           fmt::format("must be an integer in [{}, {}] (got {})", gravity::MeshGravity::kMinCells,
                       gravity::MeshGravity::kMaxCells, mesh));
  }
  g.mesh = static_cast<int>(mesh);
  g.G = r.positive("G", r.number("G", g.G));
  r.note_range("G", "CODATA 2018 by default", "m^3/(kg s^2)");
  g.dt_factor = r.within("dt_factor", r.number("dt_factor", g.dt_factor), 1e-3, 1.0, "",
                         "dt <= dt_factor sqrt(cell / max |a|); above 1 a point falls more than a "
                         "cell in one step");
  g.equilibrium = r.boolean("equilibrium", false);
  const auto& faces = scene.solver.domain.faces;
  if (g.equilibrium && !g.self) {
    // The uniform-field lithostatic start (shatter/gravity/equilibrium.hpp): gravity along -z
    // and a lower z face that bears the weight.
    const Vec3& u = scene.solver.gravity;
    const BoundaryKind floor = faces[4];
    if (!(u.z() < 0.0 && u.x() == 0.0 && u.y() == 0.0)) {
      r.fail("equilibrium",
             "needs gravity.self = true or a uniform solver.gravity along -z (the equilibrium is "
             "under self-gravity or that field)");
    }
    if (floor != BoundaryKind::fixed && floor != BoundaryKind::slip) {
      r.fail("equilibrium",
             "under a uniform field needs a 'fixed' or 'slip' z_lo face of the domain to bear "
             "the weight");
    }
  }
  const bool mirrored =
      std::find(faces.begin(), faces.end(), BoundaryKind::symmetry) != faces.end();
  if (g.self && (mirrored || scene.symmetry_axis >= 0)) {
    r.fail("self",
           "cannot be used with a symmetry plane (the mesh sees only the modelled half's "
           "mass): model the whole body");
  }
}

}  // namespace shatter::scene
