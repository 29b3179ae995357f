// The packet kernels at width 8, compiled with this ISA's flags (CMakeLists.txt). Unlike SSE and
// AVX-512, two packets in flight (simd/packet_pair.hpp) measured no faster here.
#define HEIGHTMARCH_ISA_NS isa_avx2
#include "heightmarch/simd/vfloat8_avx2.hpp"
#include "kernels/trace_range.hpp"

namespace heightmarch::isa_avx2 {

void trace_range(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                 const KernelHits& hits, std::size_t begin, std::size_t end,
                 KernelCounters& counters) {
  trace_range_packets<8>(texture, params, rays, hits, begin, end, counters);
}

}  // namespace heightmarch::isa_avx2
