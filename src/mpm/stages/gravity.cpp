// Self-gravity on the grid (issue 30): after the force-carrying P2G, the nodes' lumped masses
// m_I = sum_p m_p N_I(x_p) (Eq. 29) are the masses whose field is solved (MeshGravity), and each
// node takes the body force m_I a(x_I) (Eq. 30's b, as the uniform gravity in grid_update), so
// the particles feel it through G2P like every other nodal force. The pair forces between nodes
// are antisymmetric (mesh_gravity.hpp): the grid's momentum is conserved.

#include <memory>
#include <stdexcept>

#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "shatter/gravity/self_gravity.hpp"

namespace shatter::mpm {
namespace {

// The nodes with mass, block by block in the grid's order (one serial pass: the deposit order,
// and with it every bit of the field, is that of the grid, not of the threads).
struct NodeMasses {
  std::vector<double> x, y, z, m;
  std::vector<std::size_t> node;
};

void gather_nodes(const State& s, NodeMasses& out) {
  constexpr int B = SparseGrid::kBlock;
  const auto& N = s.grid.nodes();
  const double h = s.config.cell_size;
  for (auto* v : {&out.x, &out.y, &out.z, &out.m}) v->clear();
  out.node.clear();
  for (std::uint32_t b = 0; b < s.grid.blocks(); ++b) {
    const SparseGrid::Coord c = s.grid.coord(b);
    for (int l = 0; l < SparseGrid::kBlockNodes; ++l) {
      const std::size_t i = std::size_t{b} * SparseGrid::kBlockNodes + static_cast<std::size_t>(l);
      if (!(N.mass[i] > s.empty_mass)) continue;
      out.x.push_back(h * double(std::int64_t{c.x} * B + l / (B * B)));
      out.y.push_back(h * double(std::int64_t{c.y} * B + (l / B) % B));
      out.z.push_back(h * double(std::int64_t{c.z} * B + l % B));
      out.m.push_back(N.mass[i]);
      out.node.push_back(i);
    }
  }
}

void self_gravity(State& s, NodeMasses& nodes) {
  gather_nodes(s, nodes);
  gravity::SelfGravity& g = *s.gravity;
  g.solve({nodes.m.size(), nodes.x.data(), nodes.y.data(), nodes.z.data(), nodes.m.data()});
  auto& N = s.grid.nodes();
  for (std::size_t k = 0; k < nodes.node.size(); ++k) {
    const std::size_t i = nodes.node[k];
    N.fx[i] += nodes.m[k] * g.ax[k];
    N.fy[i] += nodes.m[k] * g.ay[k];
    N.fz[i] += nodes.m[k] * g.az[k];
  }
  g.book(s.energy, s.clock.step == 0);
}

}  // namespace

Stage self_gravity_stage(State& s) {
  // One rank only: the mesh is laid over all the mass, which a rank does not hold; the scene
  // check refuses this earlier with the key's line (src/scene/parse_gravity.cpp does not know
  // the rank count), this is the solver's own guard.
  if (s.dist()) {
    throw std::invalid_argument(
        "gravity.self = true runs on one MPI rank only (the gravity mesh needs every rank's "
        "mass; not yet distributed): run without mpirun, or set gravity.self = false");
  }
  if (!s.gravity) s.gravity = std::make_unique<gravity::SelfGravity>(s.config.self_gravity);
  auto nodes = std::make_shared<NodeMasses>();
  return {"self_gravity", {{}, kClock | kBlocks | kGrid}, {{}, kGrid | kBudget}, [&s, nodes] {
            self_gravity(s, *nodes);
          }};
}

}  // namespace shatter::mpm
