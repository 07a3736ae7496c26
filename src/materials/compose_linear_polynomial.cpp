// compose() for the linear_polynomial EOS: its own translation unit (compose_unit.hpp says why).
#include "materials/compose_unit.hpp"

SHATTER_COMPOSE(LinearPolynomial)
