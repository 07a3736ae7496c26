// compose() for the mie_gruneisen EOS: its own translation unit (compose_unit.hpp says why).
#include "materials/compose_unit.hpp"

SHATTER_COMPOSE(MieGruneisen)
