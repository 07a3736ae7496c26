// App. A.2 step 7a: strain and spin increments and the density update from the nodal
// velocities (Eqs. 21, 23); APIC's C_p; the hoop rate of the axisymmetric mode.

#include "mpm/loops.hpp"
#include "mpm/stages/stages.hpp"
#include "mpm/state.hpp"
#include "shatter/mpm/kernel_inputs.hpp"

namespace shatter::mpm {
namespace {

template <class Shape>
void velocity_gradient(State& s) {
  ParticleStore& P = s.particles;
  kernels::GradientParticles in = gradient_inputs(P, s.inv_h(), s.dt_step);
  in.stencil = s.stencil_rows<Shape>();
  if (s.transfer.affine) vgrad_columns(P, in.vgrad);
  const bool rz = s.config.geometry == Geometry::axisymmetric;  // the hoop rate v_r / r
  for_each_run<kernels::GradientWindow>(
      s.grid, [&](std::span<const std::uint32_t> run, const SparseGrid::Coord& owner,
                  const std::uint32_t* nb, kernels::GradientWindow& win) {
        if (rz) {
          kernels::velocity_gradient_block<Shape, true>(in, run, owner, nb, s.grid.nodes(), win);
        } else {
          kernels::velocity_gradient_block<Shape>(in, run, owner, nb, s.grid.nodes(), win);
        }
      });
}

}  // namespace

template <class Shape>
Stage velocity_gradient_stage(State& s) {
  const FieldSet affine = s.transfer.affine ? kVelocityGradient : FieldSet{};
  return {"velocity_gradient",
          {kGeometry, kGrid | kBlocks | kClock},
          {kStrainIncrement | kSpinIncrement | affine | FieldSet{Field::rho}, 0},
          [&s] { velocity_gradient<Shape>(s); }};
}

#define SHATTER_INSTANTIATE(S) template Stage velocity_gradient_stage<S>(State & s);
SHATTER_FOR_EACH_SHAPE(SHATTER_INSTANTIATE)

}  // namespace shatter::mpm
