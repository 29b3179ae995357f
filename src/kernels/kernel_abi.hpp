#pragma once
// What crosses the dispatch boundary: plain structs and pointers, never packet types or
// standard-library templates (they would be compiled with one ISA's flags and linked into
// another's code).
#include <cstddef>
#include <cstdint>

#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

struct KernelTexture {
  const float* texels;  // SamplerTexture layout: (width + 1) x (height + 1)
  int width, height, stride;
  Wrap wrap;
};

struct KernelParams {
  Technique technique;
  float min_layers, max_layers;
  int refine_steps;
  float scale;
  bool discard;
  float light[3];
  bool sampler_roofline;  // benchmarks only: the sampler alone instead of the technique
};

struct KernelRays {
  const float *tx, *ty, *vx, *vy, *vz;
};

struct KernelHits {
  float *u, *v, *depth, *shadow;
  std::uint32_t* samples;
  std::uint8_t* discarded;
};

struct KernelCounters {
  std::uint64_t lane_samples = 0;    // lanes that took a sample
  std::uint64_t packet_samples = 0;  // packet samples x width
};

// Traces rays [begin, end) (end - begin a multiple of the packet width) with one ISA's kernels.
using TraceRangeFn = void (*)(const KernelTexture&, const KernelParams&, const KernelRays&,
                              const KernelHits&, std::size_t begin, std::size_t end,
                              KernelCounters&);

namespace isa_scalar { void trace_range(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, std::size_t, std::size_t, KernelCounters&); }
namespace isa_sse42 { void trace_range(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, std::size_t, std::size_t, KernelCounters&); }
namespace isa_avx2 { void trace_range(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, std::size_t, std::size_t, KernelCounters&); }
namespace isa_avx512 { void trace_range(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, std::size_t, std::size_t, KernelCounters&); }

}  // namespace heightmarch
