#include "beta_output.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <spdlog/spdlog.h>

#include "shatter/io/atomic_file.hpp"

namespace shatter::cli {

BetaOutput::BetaOutput(const BetaSpec& spec, const std::filesystem::path& out)
    : spec_(spec), file_(out / "ejecta_launch.csv") {}

void BetaOutput::sample(io::TimeSeriesRow& r, double time, const ParticleStore& local,
                        const std::function<const ParticleStore&()>& all,
                        const parallel::Comm& comm) {
  BetaSums sums = beta_sums(local, spec_);
  if (comm.distributed()) {
    constexpr int L = parallel::ExactSum::kLimbs;
    std::vector<std::int64_t> limbs(sums.size() * L);
    for (std::size_t k = 0; k < sums.size(); ++k) {
      sums[k].normalise();
      std::copy(sums[k].limbs().begin(), sums[k].limbs().end(),
                limbs.begin() + static_cast<long>(k) * L);
    }
    comm.sum(limbs);
    for (std::size_t k = 0; k < sums.size(); ++k) {
      std::copy(limbs.begin() + static_cast<long>(k) * L,
                limbs.begin() + static_cast<long>(k + 1) * L, sums[k].limbs().begin());
    }
  }
  // p_imp from the impactor's mass at the first sample (kept in the launch table, so a resume
  // has it too): impactor points that leave the domain later must not shrink it.
  if (launches_.impactor_mass() == 0.0) launches_.set_impactor(sums[2].value(), spec_.impact_speed);
  const BetaSample b = beta_sample(sums, spec_, launches_.impactor_mass());
  r.ejecta_mass = b.ejecta_mass;
  r.ejecta_momentum = b.ejecta_momentum;
  r.impactor_momentum = b.impactor_momentum;
  r.beta = b.beta;
  r.beta_target = b.beta_target;
  // The launch record (Housen & Holsapple 2011's M(>v)) at the same samples.
  const ParticleStore& every = all();
  if (comm.rank() == 0 && time == 0.0) warn_if_above(every);
  if (comm.rank() == 0) {
    launches_.record(every, spec_, time);
    r.beta_launch = launches_.beta_at_launch(spec_.escape_speed);  // only rank 0 writes rows
  }
}

void BetaOutput::warn_if_above(const ParticleStore& store) const {
  // The launch count assumes the target starts below the control plane (a flat surface): a
  // point above it is "launched" the first time it moves outward, however slowly.
  const auto m = store.col(Field::mass);
  const auto body = store.col(IField::body);
  double above = 0.0, total = 0.0;
  for (std::size_t p = 0; p < store.size(); ++p) {
    if (body[p] == spec_.impactor) continue;
    const Eigen::Vector3d x(store.col(Field::x)[p], store.col(Field::y)[p], store.col(Field::z)[p]);
    total += m[p];
    if ((x - spec_.surface_point).dot(spec_.normal) > 0.0) above += m[p];
  }
  if (above > 0.0) {
    spdlog::warn(
        "beta: {:.3g} of the non-impactor mass starts above the control plane (beta.surface, "
        "beta.normal): beta_launch and ejecta_launch.csv count it as launched when it first "
        "moves outward; they are meant for a flat target surface (docs/validation-dart.md)",
        above / total);
  }
}

void BetaOutput::write() const {
  io::write_text_atomically(file_, launches_.csv());
}

bool BetaOutput::resume(double time) {
  try {
    std::ifstream in(file_, std::ios::binary);
    if (!in) throw std::runtime_error(file_.string() + ": missing");
    std::stringstream text;
    text << in.rdbuf();
    launches_.read(text.str(), file_.string(), time);
  } catch (const std::exception& e) {
    spdlog::error("{} (the ejecta launch table a [beta] scene resumes from)", e.what());
    return false;
  }
  return true;
}

}  // namespace shatter::cli
