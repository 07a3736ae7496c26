#pragma once
// Public since issue 28 (include/shatter/mpm/boundaries.hpp: the stage benchmarks in bench/ time
// the engine's own nodal pass through it); the engine's files still include it by this path.
#include "shatter/mpm/boundaries.hpp"
