// The packet kernels at width 1, compiled with this ISA's flags (CMakeLists.txt).
#define HEIGHTMARCH_ISA_NS isa_scalar
#include "heightmarch/simd/vfloat1.hpp"
#include "kernels/kernel_table.hpp"

namespace heightmarch::isa_scalar {

const KernelTable& kernel_table() {
  // Constant-initialised: no code of this ISA runs before the CPU is known to support it.
  static constexpr KernelTable table = make_kernel_table<1>();
  return table;
}

}  // namespace heightmarch::isa_scalar
