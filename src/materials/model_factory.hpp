#pragma once
// Parameter sets -> kernel model objects. The variants list every EOS and strength kernel; the
// composed constitutive model is instantiated per (EOS, strength, damage) combination.

#include <variant>

#include "eos/ideal_gas.hpp"
#include "eos/linear_elastic.hpp"
#include "eos/linear_polynomial.hpp"
#include "eos/mie_gruneisen.hpp"
#include "eos/tillotson.hpp"
#include "eos/tillotson_simplified.hpp"
#include "shatter/material/catalogue.hpp"
#include "strength/benz_asphaug.hpp"
#include "strength/drucker_prager.hpp"
#include "strength/elastic.hpp"
#include "strength/hydro.hpp"
#include "strength/j2_plasticity.hpp"
#include "strength/lundborg.hpp"
#include "strength/modified_lundborg.hpp"

namespace shatter::materials {

using AnyEos = std::variant<eos::Tillotson, eos::TillotsonSimplified, eos::MieGruneisen,
                            eos::LinearPolynomial, eos::LinearElastic, eos::IdealGas>;
using AnyStrength =
    std::variant<strength::Hydro, strength::Elastic, strength::J2Plasticity, strength::BenzAsphaug,
                 strength::DruckerPrager, strength::Lundborg, strength::ModifiedLundborg>;

// Both expect a validated spec.
AnyEos make_eos(const MaterialSpec& spec);
AnyStrength make_strength(const MaterialSpec& spec);

}  // namespace shatter::materials
