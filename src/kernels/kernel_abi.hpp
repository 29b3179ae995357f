#pragma once
// What crosses the dispatch boundary: plain structs and pointers, never packet types or
// standard-library templates (they would be compiled with one ISA's flags and linked into
// another's code).
#include <cstddef>
#include <cstdint>

#include "heightmarch/isa.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

struct KernelTexture {
  const float* texels;  // SamplerTexture layout: (width + 1) x (height + 1)
  int width, height, stride;
  Wrap wrap;
  // The min-depth pyramid (MinDepthPyramid's flat layout) for the techniques that walk it;
  // null with 0 levels otherwise. A level's blocks a side follow from the map's size.
  const float* pyramid = nullptr;
  const std::int32_t* level_offsets = nullptr;
  int pyramid_levels = 0;
  // The relaxed cone map's ratios in the texels' layout (cone only; heightmarch/cone_map.hpp).
  const float* cone = nullptr;
  // Trilinear: the mip chain's levels (SamplerTexture's), level 0 first; the texels hold them all
  // (and the cone map's ratios theirs, alike). Bilinear samplers read level 0 alone.
  const SamplerLevel* levels = nullptr;
  int level_count = 1;
};

struct KernelParams {
  float min_layers, max_layers;
  int refine_steps;
  float scale;
  bool discard;
  float light[3];
};

struct KernelRays {
  const float *tx, *ty, *vx, *vy, *vz;
  const float *du_dx = nullptr, *dv_dx = nullptr, *du_dy = nullptr, *dv_dy = nullptr;  // trilinear only
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

// Traces rays [begin, end) (end - begin a multiple of the packet width) with one technique of one
// ISA, for one addressing mode of the texture.
using TraceRangeFn = void (*)(const KernelTexture&, const KernelParams&, const KernelRays&,
                              const KernelHits&, std::size_t begin, std::size_t end,
                              KernelCounters&);

// How the sampler finds texel indices: REPEAT on power-of-two sides is a mask of the integer
// index, other REPEAT sizes wrap in float, CLAMP clamps the coordinate.
enum class Addressing { repeat_pow2, repeat, clamp };
inline constexpr int kAddressingCount = 3;

inline Addressing addressing_of(int width, int height, Wrap wrap) {
  if (wrap == Wrap::clamp) return Addressing::clamp;
  const bool pow2 = (width & (width - 1)) == 0 && (height & (height - 1)) == 0;
  return pow2 ? Addressing::repeat_pow2 : Addressing::repeat;
}

// What each ISA exports: its kernels, chosen once by a Tracer, never per tile.
struct KernelTable {
  int packet_width;  // rays per loop iteration
  TraceRangeFn technique[kTechniqueCount][kFilterCount][kAddressingCount];
  TraceRangeFn sampler_roofline[kFilterCount][kAddressingCount];  // the sampler alone (benchmarks)
  // The exact reference's float pass (src/exact/exact_hits.cpp): per ray, with shadow 1 the exact
  // hit (uv, depth), found in double in the cell the pass stopped in; with shadow 0, in depth, how
  // far the path is certainly clear of the surface. In samples, the cells it tested in float.
  TraceRangeFn exact_bound[kAddressingCount];
  TraceRangeFn compute_ceiling[kFilterCount][kAddressingCount];  // POM on register taps (benchmarks)
  // The naive port vectorised by the compiler (benchmarks), on a plain REPEAT DepthMap
  // (stride = width) instead of the sampler's layout.
  TraceRangeFn autovec_pom;
};

#define HEIGHTMARCH_ISA_KERNEL_TABLE(id, ...)                                                        \
  namespace isa_##id {                                                                               \
  const KernelTable& kernel_table();                                                                 \
  void autovec_pom(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, \
                   std::size_t, std::size_t, KernelCounters&); /* src/isa/autovec_<id>.cpp */        \
  }
HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_KERNEL_TABLE)
#undef HEIGHTMARCH_ISA_KERNEL_TABLE

// The table of a given ISA.
const KernelTable& kernel_table(Isa isa);

}  // namespace heightmarch
