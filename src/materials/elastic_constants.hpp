#pragma once
// Elastic constants of a parameter set, from (young, poisson) or (shear_modulus, bulk_modulus).

#include "shatter/material/catalogue.hpp"
#include "strength/strength_common.hpp"

namespace shatter::materials {

bool has_elastic_pair(const MaterialSpec& spec);
bool has_any_elastic_key(const MaterialSpec& spec);
// Throws MaterialError naming the missing or non-physical key.
strength::ElasticConstants elastic_constants(const MaterialSpec& spec);

}  // namespace shatter::materials
