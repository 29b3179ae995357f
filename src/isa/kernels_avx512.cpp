// The packet kernels at width 16, compiled with this ISA's flags (CMakeLists.txt).
#define HEIGHTMARCH_ISA_NS isa_avx512
#include "heightmarch/simd/vfloat16_avx512.hpp"
#include "kernels/trace_range.hpp"

namespace heightmarch::isa_avx512 {

void trace_range(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                 const KernelHits& hits, std::size_t begin, std::size_t end,
                 KernelCounters& counters) {
  trace_range_packets<16>(texture, params, rays, hits, begin, end, counters);
}

}  // namespace heightmarch::isa_avx512
