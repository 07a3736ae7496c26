// compose() for the linear_elastic EOS: its own translation unit (compose_unit.hpp says why).
#include "materials/compose_unit.hpp"

SHATTER_COMPOSE(LinearElastic)
