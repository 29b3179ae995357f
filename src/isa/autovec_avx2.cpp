// The naive port vectorised by the compiler, with this ISA's flags (CMakeLists.txt).
#include "kernels/kernel_abi.hpp"  // first: with HEIGHTMARCH_ISA_NS defined it would pull in every kernel
#define HEIGHTMARCH_ISA_NS isa_avx2
#include "baselines/autovec_port.hpp"
