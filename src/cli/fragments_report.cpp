#include "fragments_report.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "shatter/io/mirror.hpp"

namespace shatter::cli {

FragmentCatalogue report_fragments(const ParticleStore& particles, int symmetry_axis,
                                   const FragmentSearchSpec& spec,
                                   const std::filesystem::path& prefix) {
  // A fragment cut by the symmetry plane is one fragment: search the whole body.
  ParticleStore full = symmetry_axis >= 0 ? io::mirrored(particles, symmetry_axis) : particles;
  const FragmentCatalogue cat = find_fragments(full, spec);
  auto with_ext = [&](const char* ext) {
    std::filesystem::path p = prefix;
    p += ext;
    return p;
  };
  write_fragments_csv(cat, with_ext(".csv"));
  write_fragments_hdf5(cat, with_ext(".h5"));
  write_fragments_pkdgrav(cat, with_ext(".pkdgrav"));
  spdlog::info(
      "{} fragments (D < {}), dust {:.3g} kg of {:.3g} kg{}; written to {}.csv/.h5/.pkdgrav",
      cat.fragments.size(), spec.damage_threshold, cat.dust_mass, cat.total_mass,
      symmetry_axis >= 0 ? " (half model mirrored)" : "", prefix.string());
  const std::size_t shown = std::min<std::size_t>(cat.fragments.size(), 5);
  for (std::size_t i = 0; i < shown; ++i) {
    const Fragment& f = cat.fragments[i];
    spdlog::info("  fragment {}: {} points, m = {:.4g} kg ({:.3g} of total), |v| = {:.4g} m/s", i,
                 f.particles, f.mass, f.mass / cat.total_mass, f.velocity.norm());
  }
  return cat;
}

}  // namespace shatter::cli
