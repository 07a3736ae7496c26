#include "materials/damage_factory.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "materials/schema.hpp"

namespace shatter::materials {

AnyDamage make_damage(const DamageSpec& spec) {
  if (spec.model == "none") {
    if (!spec.params.empty()) {
      throw std::invalid_argument(fmt::format("damage model 'none' takes no parameters (got '{}')",
                                              spec.params.begin()->first));
    }
    return damage::NoDamage{};
  }
  for (auto known : damage_models()) {
    if (known == spec.model) {
      throw std::invalid_argument(
          fmt::format("damage model '{}' is not available in this build of the material library "
                      "(available: none)",
                      spec.model));
    }
  }
  throw std::invalid_argument(fmt::format("unknown damage model '{}' (known: {})", spec.model,
                                          join_names(damage_models())));
}

}  // namespace shatter::materials
