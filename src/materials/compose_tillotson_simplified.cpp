// compose() for the tillotson_simplified EOS: its own translation unit (compose_unit.hpp says why).
#include "materials/compose_unit.hpp"

SHATTER_COMPOSE(TillotsonSimplified)
