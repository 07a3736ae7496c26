// The Morris & Monaghan (1997) viscosity switch (SphConfig::viscosity_switch): alpha per
// particle, a state that follows the particles through the re-order and the outflow, evolved
// once per step (kernels/sph/terms.hpp morris_monaghan_alpha).

#include <algorithm>

#include <tbb/parallel_for.h>

#include "sph/solver_impl.hpp"

namespace shatter::sph {

void SphSolver::Impl::start_switch() {
  switch_on = s.sph_.viscosity_switch == ViscositySwitch::morris_monaghan;
  switch_k = {s.sph_.alpha_min, s.sph_.alpha_max, s.sph_.switch_decay};
  // Every particle starts at alpha_max, the constant default's viscosity at the first contact
  // of an impact, and decays where nothing converges (in tau = h / (C c), a few sound
  // crossings of h).
  if (switch_on) alpha.assign(s.particles_.size(), s.sph_.alpha_max);
}

// The switch over this step (terms.hpp morris_monaghan_alpha): div v from the step's volume
// change, tr deps / dt (= div v rho^n / rho^{n+1}, the rates pass's estimate), c^{n+1} from
// the material update and h^{n+1/2}; the forces at t^{n+1} then use alpha^{n+1}.
void SphSolver::Impl::evolve_switch(double dt) {
  if (!switch_on) return;
  ParticleStore& P = s.particles_;
  const double* d[3] = {P.col(Field::deps_xx).data(), P.col(Field::deps_yy).data(),
                        P.col(Field::deps_zz).data()};
  const double* c = P.col(Field::soundspeed).data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, P.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        const double div_v = (d[0][p] + d[1][p] + d[2][p]) / dt;
                        alpha[p] = ks::morris_monaghan_alpha(switch_k, alpha[p], div_v, c[p],
                                                             h_mid[p], dt);
                      }
                    });
}

// After the store's permute(order): new particle k is old particle order[k], as in
// ParticleStore::permute (rho_n serves as the scratch copy).
void SphSolver::Impl::permute_switch() {
  if (!switch_on) return;
  const std::size_t n = s.particles_.size();
  // heat as the scratch copy (free in the search stage: the forces pass rewrites it).
  heat.resize(n);
  for (std::size_t k = 0; k < n; ++k) heat[k] = alpha[order[k]];
  std::copy(heat.begin(), heat.begin() + static_cast<std::ptrdiff_t>(n), alpha.begin());
}

// After the outflow removed the particles marked in `leaving` (of the n before it): their alpha
// leaves with them (the store keeps the order of the rest).
void SphSolver::Impl::drop_leaving_switch(std::size_t n) {
  if (!switch_on) return;
  std::size_t k = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (leaving[p] == 0) alpha[k++] = alpha[p];
  }
  alpha.resize(k);
}

}  // namespace shatter::sph
