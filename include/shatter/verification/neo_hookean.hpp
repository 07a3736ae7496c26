#pragma once
// Compressible neo-Hookean solid under uniaxial strain (laterally confined, F = diag(F, 1, 1)):
// the constitutive law of the manufactured-solution problem (verification-problems.md, problem 2).
// With J = F the Cauchy stress of sigma = mu/J (B - I) + lambda ln(J)/J I reduces to
//   sigma_xx = lambda ln(F) / F + mu (F - 1/F),   sigma_yy = sigma_zz = lambda ln(F) / F,
// and, since J F^{-1} = 1 along x, the first Piola-Kirchhoff stress P_xx equals sigma_xx.
// F is recovered from the density alone, F = rho0 / rho, so the model needs no extra column and
// is exact only for motions along x (which is what the 1D problems are).

#include <string>

#include "shatter/material/material_model.hpp"

namespace shatter::verification {

class UniaxialNeoHookean final : public MaterialModel {
 public:
  // Throws std::invalid_argument for rho0 <= 0, E <= 0 or Poisson outside [0, 0.5).
  UniaxialNeoHookean(double density, double young, double poisson);

  std::string name() const override { return "neo_hookean_uniaxial"; }
  double reference_density() const override { return rho0_; }
  void initialise(ParticleStore& store, Range range) const override;
  void update(ParticleStore& store, Range range, const ConstitutiveContext& ctx) const override;

  double lambda() const { return lambda_; }
  double mu() const { return mu_; }
  // P(F) = sigma_xx(F), the axial stress of the law above.
  double axial_stress(double F) const;
  // Lateral stress sigma_yy = sigma_zz = lambda ln(F) / F.
  double lateral_stress(double F) const;
  // dP/dF = mu (1 + 1/F^2) + lambda (1 - ln F) / F^2: the Lagrangian tangent modulus.
  double tangent(double F) const;
  // Longitudinal wave speed in the current configuration, F sqrt(dP/dF / rho0) (the Lagrangian
  // speed sqrt(dP/dF / rho0) stretched by F), used by the time step (Eq. 34).
  double wave_speed(double F) const;

 private:
  double rho0_, lambda_, mu_;
};

}  // namespace shatter::verification
