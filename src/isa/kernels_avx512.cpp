// The packet kernels at width 2 x 16: two native 16-wide packets in flight per loop iteration
// (simd/packet_pair.hpp; measured faster than one), compiled with this ISA's flags (CMakeLists.txt).
#define HEIGHTMARCH_ISA_NS isa_avx512
#include "heightmarch/simd/vfloat16_avx512.hpp"
#define HEIGHTMARCH_PAIR_OF 16
#include "heightmarch/simd/packet_pair.hpp"
#include "kernels/trace_range.hpp"

namespace heightmarch::isa_avx512 {

void trace_range(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                 const KernelHits& hits, std::size_t begin, std::size_t end,
                 KernelCounters& counters) {
  trace_range_packets<2 * 16>(texture, params, rays, hits, begin, end, counters);
}

}  // namespace heightmarch::isa_avx512
