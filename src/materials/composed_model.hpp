#pragma once
// ComposedModel: the MaterialModel of one material group, a thin shell around the compile-time
// composed kernel (kernels/constitutive/composed_kernel.hpp). One virtual call per group and
// step; the particle loop inside has no model branches.

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <variant>

#include "constitutive/composed_kernel.hpp"
#include "materials/damage_factory.hpp"
#include "materials/model_factory.hpp"
#include "shatter/material/material_model.hpp"

namespace shatter::materials {

// Column pointers of the store. Throws std::logic_error naming a column of `needed` that the
// scene did not register. With increments = false the deps/dspin columns are not looked up.
constitutive::ConstitutiveColumns gather_columns(ParticleStore& store, FieldSet needed,
                                                 bool increments);

template <class Eos, class Strength, class Damage, class Porosity = porosity::NoPorosity>
class ComposedModel final : public MaterialModel {
 public:
  ComposedModel(std::string name, Eos eos, Strength strength, Damage damage,
                constitutive::DamageCoupling coupling, Porosity porosity = {})
      : name_(std::move(name)), kernel_(eos, strength, damage, coupling, porosity) {}

  std::string name() const override { return name_; }

  FieldSet fields() const override {
    // The peak-pressure tracer is every composed material's, so both solvers (MPM and SPH, which
    // call update() per group) keep it without code of their own.
    FieldSet f =
        Strength::kFields | Damage::kFields | Porosity::kFields | FieldSet{Field::peak_pressure};
    if constexpr (Damage::kEnabled) f = f | kDeviator;
    return f;
  }

  // The bulk density at rest: the matrix's over the initial distension (1 without porosity).
  double reference_density() const override {
    if constexpr (Porosity::kEnabled) {
      return kernel_.eos().reference_density() / kernel_.porosity().alpha0();
    } else {
      return kernel_.eos().reference_density();
    }
  }

  void initialise(ParticleStore& store, Range range) const override {
    kernel_.initialise(gather_columns(store, fields(), false), range.begin, range.end);
    if (!store.has(Field::peak_pressure)) return;  // a store made without the model's fields
    const auto p = store.col(Field::pressure);
    auto peak = store.col(Field::peak_pressure);
    for (std::size_t k = range.begin; k < range.end; ++k) peak[k] = p[k];
  }

  void update(ParticleStore& store, Range range, const ConstitutiveContext& ctx) const override {
    const constitutive::StepParams sp{ctx.dt, ctx.cell_size, ctx.viscosity.linear,
                                      ctx.viscosity.quadratic};
    auto columns = gather_columns(store, fields(), false);
    const IncrementViews inc = increments_of(store, ctx);
    for (int k = 0; k < 6; ++k) columns.deps[k] = inc.deps[k];
    for (int k = 0; k < 3; ++k) columns.dspin[k] = inc.dspin[k];
    columns.increments_begin = inc.begin;
    if (ctx.rings) columns.ring_radius = store.col(Field::x).data();
    kernel_.update(columns, range.begin, range.end, sp);
    // Peak-pressure tracer: the largest EOS pressure (the kernel's step 3, Eqs. 8-12) seen so
    // far, what iSALE and CTH report as peak shock pressure. Per point: thread-independent.
    if (!store.has(Field::peak_pressure)) return;
    const auto p = store.col(Field::pressure);
    auto peak = store.col(Field::peak_pressure);
    for (std::size_t k = range.begin; k < range.end; ++k) peak[k] = std::max(peak[k], p[k]);
  }

  const constitutive::ComposedKernel<Eos, Strength, Damage, Porosity>& kernel() const {
    return kernel_;
  }

 private:
  std::string name_;
  constitutive::ComposedKernel<Eos, Strength, Damage, Porosity> kernel_;
};

template <class Eos>
MaterialPtr compose_with(const Eos& eos, const AnyStrength& strength, const AnyDamage& damage,
                         constitutive::DamageCoupling coupling, const std::string& name) {
  return std::visit(
      [&](const auto& s, const auto& d) -> MaterialPtr {
        using S = std::decay_t<decltype(s)>;
        using D = std::decay_t<decltype(d)>;
        return std::make_shared<const ComposedModel<Eos, S, D>>(name, eos, s, d, coupling);
      },
      strength, damage);
}

// The same with the porosity stage (kernels/porosity/porosity.hpp): compose_porous_<eos>.cpp.
template <class Eos>
MaterialPtr compose_porous_with(const Eos& eos, const AnyStrength& strength,
                                const AnyDamage& damage, constitutive::DamageCoupling coupling,
                                const porosity::Porous& por, const std::string& name) {
  return std::visit(
      [&](const auto& s, const auto& d) -> MaterialPtr {
        using S = std::decay_t<decltype(s)>;
        using D = std::decay_t<decltype(d)>;
        return std::make_shared<const ComposedModel<Eos, S, D, porosity::Porous>>(name, eos, s, d,
                                                                                  coupling, por);
      },
      strength, damage);
}

// One translation unit per EOS (compose_<eos>.cpp) keeps the instantiations apart.
MaterialPtr compose(const eos::Tillotson&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);
MaterialPtr compose(const eos::TillotsonSimplified&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);
MaterialPtr compose(const eos::MieGruneisen&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);
MaterialPtr compose(const eos::LinearPolynomial&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);
MaterialPtr compose(const eos::LinearElastic&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);
MaterialPtr compose(const eos::IdealGas&, const AnyStrength&, const AnyDamage&,
                    constitutive::DamageCoupling, const std::string&);

MaterialPtr compose_porous(const eos::Tillotson&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);
MaterialPtr compose_porous(const eos::TillotsonSimplified&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);
MaterialPtr compose_porous(const eos::MieGruneisen&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);
MaterialPtr compose_porous(const eos::LinearPolynomial&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);
MaterialPtr compose_porous(const eos::LinearElastic&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);
MaterialPtr compose_porous(const eos::IdealGas&, const AnyStrength&, const AnyDamage&,
                           constitutive::DamageCoupling, const porosity::Porous&,
                           const std::string&);

}  // namespace shatter::materials
