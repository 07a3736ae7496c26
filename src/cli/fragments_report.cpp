#include "fragments_report.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "shatter/fracture/bound_remnant.hpp"
#include "shatter/gravity/mesh_gravity.hpp"
#include "shatter/io/mirror.hpp"

namespace shatter::cli {
namespace {

// Shrinks the radii when asked (output.ss_radius = "packing_safe") and says how many.
SsFile sized(SsFile ss, SsRadius radius, const std::string& what) {
  if (radius != SsRadius::packing_safe) return ss;
  const std::size_t shrunk = apply_packing_safe_radius(ss);
  spdlog::info(
      "{}: packing-safe radii: {} of {} records shrunk to half their nearest-neighbour "
      "distance",
      what, shrunk, ss.records.size());
  return ss;
}

// PREFIX.ss (one record per fragment) and, when asked, PREFIX_particles.ss (one per point). A
// catalogue without fragments (every point failed, common at km scale) would give an ss file of
// no records, which pkdgrav's tools refuse: PREFIX.ss then holds every point instead, said so.
template <class WithExt>
void write_hand_off(const FragmentCatalogue& cat, const ParticleStore& full,
                    const FragmentSearchSpec& spec, const WithExt& with_ext,
                    const FragmentReportInfo& info) {
  const auto ss_file = with_ext(".ss");
  if (cat.fragments.empty()) {
    spdlog::warn(
        "no fragment survives: all {} points have D >= {} (dust {:.3g} kg); {} holds every point "
        "instead (one record each, colour {}), the input of a rubble-pile reaccumulation",
        full.size(), spec.damage_threshold, cat.dust_mass, ss_file.string(), kSsDustColour);
    write_ss(sized(particles_ss(full, info.time), spec.ss_radius, ss_file.string()), ss_file);
  } else {
    write_ss(sized(fragments_ss(cat, info.time), spec.ss_radius, ss_file.string()), ss_file);
  }
  if (info.ss_particles) {
    const auto file = with_ext("_particles.ss");
    write_ss(sized(particles_ss(full, info.time), spec.ss_radius, file.string()), file);
  }
}

}  // namespace

FragmentCatalogue report_fragments(const ParticleStore& particles, int symmetry_axis,
                                   const FragmentSearchSpec& spec,
                                   const std::filesystem::path& prefix,
                                   const FragmentReportInfo& info) {
  // A fragment cut by the symmetry plane is one fragment: search the whole body. In r-z the axis
  // is not a mirror plane: the rings already are the whole body, searched in the half-plane.
  const bool rz = spec.axisymmetric;
  ParticleStore full =
      symmetry_axis >= 0 && !rz ? io::mirrored(particles, symmetry_axis) : particles;
  full.require(IField::fragment);  // labels, for the composition and the particle ss file
  FragmentCatalogue cat = find_fragments(full, spec);
  if (!info.body_names.empty() && full.has(IField::body)) {
    add_composition(cat, full, info.body_names, info.body_materials);
  }
  auto with_ext = [&](const char* ext) {
    std::filesystem::path p = prefix;
    p += ext;
    return p;
  };
  write_fragments_csv(cat, with_ext(".csv"));
  write_fragments_hdf5(cat, with_ext(".h5"));
  if (rz) {
    // pkdgrav's spheres and BA99's point-mass binding energies cannot stand for rings: a ring off
    // the axis is neither a sphere at its centre nor a point mass (bound_remnant* is written for
    // 3-D points), so in r-z both are skipped rather than computed wrongly.
    spdlog::info(
        "r-z: {} fragments (bodies of revolution; {} off the axis are rings) of the model, dust "
        "{:.3g} kg of {:.3g} kg; written to {}.csv/.h5 (no .ss hand-off and no bound remnant in "
        "r-z: rings are not spheres or point masses)",
        cat.fragments.size(),
        std::count_if(cat.fragments.begin(), cat.fragments.end(),
                      [](const Fragment& f) { return !f.touches_axis; }),
        cat.dust_mass, cat.total_mass, prefix.string());
    return cat;
  }
  write_hand_off(cat, full, spec, with_ext, info);
  // BA99's bound remnant, the dust points as bodies of their own (a shattered body is dust)
  const BoundRemnant bound = bound_remnant_with_dust(cat, full, gravity::kNewtonG);
  write_bound_remnant_json(bound, cat, with_ext("_bound.json"));
  spdlog::info(
      "bound remnant (BA99): m = {:.4g} kg ({:.3g} of total), {} fragments and {} dust points "
      "(seed: {}), |v| = {:.4g} m/s, spin {:.4g} rad/s; written to {}_bound.json",
      bound.mass, cat.total_mass > 0.0 ? bound.mass / cat.total_mass : 0.0, bound.members.size(),
      bound.dust_points, bound.seed, bound.speed(), bound.spin(), prefix.string());
  const char* model = symmetry_axis >= 0 ? "the mirrored body (half model mirrored)" : "the model";
  spdlog::info(
      "{} fragments (D < {}) of {}, dust {:.3g} kg of {:.3g} kg; written to {}.csv/.h5/.ss{}",
      cat.fragments.size(), spec.damage_threshold, model, cat.dust_mass, cat.total_mass,
      prefix.string(), info.ss_particles ? " and _particles.ss" : "");
  const std::size_t shown = std::min<std::size_t>(cat.fragments.size(), 5);
  for (std::size_t i = 0; i < shown; ++i) {
    const Fragment& f = cat.fragments[i];
    std::string made_of;
    for (std::size_t b = 0; b < f.mass_by_body.size(); ++b) {
      if (f.mass_by_body[b] > 0.0) {
        made_of += fmt::format("{}{} {:.2g}", made_of.empty() ? ", " : " + ", cat.body_names[b],
                               f.mass_by_body[b] / f.mass);
      }
    }
    spdlog::info("  fragment {}: {} points, m = {:.4g} kg ({:.3g} of total), |v| = {:.4g} m/s{}", i,
                 f.particles, f.mass, f.mass / cat.total_mass, f.velocity.norm(), made_of);
  }
  return cat;
}

}  // namespace shatter::cli
