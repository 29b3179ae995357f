// The packet kernels at width 8, compiled with this ISA's flags (CMakeLists.txt). Unlike SSE and
// AVX-512, two packets in flight (simd/packet_pair.hpp) measured no faster here.
#define HEIGHTMARCH_ISA_NS isa_avx2
#include "heightmarch/simd/vfloat8_avx2.hpp"
#include "kernels/kernel_table.hpp"

namespace heightmarch::isa_avx2 {

const KernelTable& kernel_table() {
  // Constant-initialised: no code of this ISA runs before the CPU is known to support it.
  static constexpr KernelTable table = make_kernel_table<8>();
  return table;
}

}  // namespace heightmarch::isa_avx2
