// The packet kernels at width 2 x 16: two native 16-wide packets in flight per loop iteration
// (simd/packet_pair.hpp; measured faster than one), except maxmip at one (kernel_table.hpp),
// compiled with this ISA's flags (CMakeLists.txt).
#define HEIGHTMARCH_ISA_NS isa_avx512
#include "heightmarch/simd/vfloat16_avx512.hpp"
#define HEIGHTMARCH_PAIR_OF 16
#include "heightmarch/simd/packet_pair.hpp"
#include "kernels/kernel_table.hpp"

namespace heightmarch::isa_avx512 {

const KernelTable& kernel_table() {
  // Constant-initialised: no code of this ISA runs before the CPU is known to support it.
  static constexpr KernelTable table = make_kernel_table<2 * 16, 16>();
  return table;
}

}  // namespace heightmarch::isa_avx512
