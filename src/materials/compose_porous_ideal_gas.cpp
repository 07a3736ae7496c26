// compose_porous() for the ideal_gas EOS, with the porosity stage: its own translation unit
// (compose_unit.hpp says why).
#include "materials/compose_unit.hpp"

SHATTER_COMPOSE_POROUS(IdealGas)
