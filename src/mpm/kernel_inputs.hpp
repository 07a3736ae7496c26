#pragma once
// Public since issue 28 (include/shatter/mpm/kernel_inputs.hpp: the stage benchmarks in bench/
// run the kernels on the engine's own inputs); the stages still include it by this path.
#include "shatter/mpm/kernel_inputs.hpp"
