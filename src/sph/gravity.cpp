// Self-gravity in the SPH force pass (issue 30): the particles are the masses of the mesh solve
// (shatter/gravity/self_gravity.hpp), and their acceleration joins Eq. 17's after the pair
// gather. The force condition of the time step (time_step.cpp, dt_f = cfl sqrt(h / |a|)) then
// includes gravity; W joins the energy budget, before E.initial is taken at set-up.

#include <memory>

#include <tbb/parallel_for.h>

#include "sph/solver_impl.hpp"

namespace shatter::sph {

void SphSolver::Impl::add_self_gravity() {
  ParticleStore& P = s.particles_;
  const std::size_t n = P.size();  // real particles only: images are not mass
  if (!gravity) gravity = std::make_unique<gravity::SelfGravity>(s.config_.self_gravity);
  gravity->solve({n, P.col(Field::x).data(), P.col(Field::y).data(), P.col(Field::z).data(),
                  P.col(Field::mass).data()});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        ax[p] += gravity->ax[p];
                        ay[p] += gravity->ay[p];
                        az[p] += gravity->az[p];
                      }
                    });
  gravity->book(s.energy_, false);
}

}  // namespace shatter::sph
