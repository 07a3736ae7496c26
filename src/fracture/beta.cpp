// beta = 1 + p_ej / p_imp from the particles (include/shatter/fracture/beta.hpp).

#include "shatter/fracture/beta.hpp"

#include "point_motion.hpp"

namespace shatter {

bool is_ejecta(const BetaSpec& spec, const Eigen::Vector3d& x, const Eigen::Vector3d& v) {
  // Above the pre-impact surface and moving out of the target (Raducan et al. 2019, Sec. 2).
  if (!((x - spec.surface_point).dot(spec.normal) > 0.0)) return false;
  if (!(v.dot(spec.normal) > 0.0)) return false;
  // Faster than the escape speed, when the scene's target has one (Stickle et al. 2022).
  return spec.escape_speed <= 0.0 || v.squaredNorm() >= spec.escape_speed * spec.escape_speed;
}

BetaSums beta_sums(const ParticleStore& store, const BetaSpec& spec) {
  BetaSums s;
  const fracture::PointMotion pts(store);
  const auto body = store.col(IField::body);
  const Eigen::Vector3d& d = spec.direction;
  for (std::size_t p = 0; p < store.size(); ++p) {
    const Eigen::Vector3d vp = pts.velocity(p);
    const double along = pts.mass[p] * vp.dot(d);  // m_p v_p . d
    if (is_ejecta(spec, pts.position(p), vp)) {
      s[0].add(pts.mass[p]);
      s[1].add(-along);
    } else {
      s[3].add(along);
    }
    if (body[p] == spec.impactor) s[2].add(pts.mass[p]);
  }
  return s;
}

BetaSample beta_sample(BetaSums& sums, const BetaSpec& spec, double impactor_mass) {
  BetaSample b;
  b.ejecta_mass = sums[0].value();
  b.ejecta_momentum = sums[1].value();
  b.impactor_momentum = impactor_mass * spec.impact_speed;
  if (b.impactor_momentum > 0.0) {
    b.beta = 1.0 + b.ejecta_momentum / b.impactor_momentum;
    b.beta_target = sums[3].value() / b.impactor_momentum;
  }
  return b;
}

BetaSample measure_beta(const ParticleStore& store, const BetaSpec& spec) {
  auto s = beta_sums(store, spec);
  return beta_sample(s, spec, s[2].value());
}

}  // namespace shatter
