// The packet kernels at width 2 x 4: two native 4-wide packets in flight per loop iteration
// (simd/packet_pair.hpp; measured faster than one), compiled with this ISA's flags (CMakeLists.txt).
#define HEIGHTMARCH_ISA_NS isa_sse42
#include "heightmarch/simd/vfloat4_sse.hpp"
#define HEIGHTMARCH_PAIR_OF 4
#include "heightmarch/simd/packet_pair.hpp"
#include "kernels/kernel_table.hpp"

namespace heightmarch::isa_sse42 {

const KernelTable& kernel_table() {
  // Constant-initialised: no code of this ISA runs before the CPU is known to support it.
  static constexpr KernelTable table = make_kernel_table<2 * 4>();
  return table;
}

}  // namespace heightmarch::isa_sse42
