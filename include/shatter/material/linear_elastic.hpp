#pragma once
// Linear elastic solid with the Jaumann stress rate (Eqs. 22, 35–37): the engine's own material,
// so the MUSL step is testable without the material library.

#include "shatter/material/material_model.hpp"

namespace shatter {

class LinearElastic final : public MaterialModel {
 public:
  // Throws std::invalid_argument for non-physical parameters (rho0 <= 0, E <= 0,
  // Poisson outside [0, 0.5)).
  LinearElastic(double density, double young, double poisson);

  std::string name() const override { return "linear_elastic"; }
  double reference_density() const override { return rho0_; }
  void initialise(ParticleStore& store, Range range) const override;
  void update(ParticleStore& store, Range range, const ConstitutiveContext& ctx) const override;

  double bulk_modulus() const { return bulk_; }
  double shear_modulus() const { return shear_; }
  // Laterally confined longitudinal speed c_p = sqrt((K + 4G/3) / rho) at density rho.
  double longitudinal_speed(double rho) const;

 private:
  double rho0_, young_, poisson_, bulk_, shear_;
};

}  // namespace shatter
