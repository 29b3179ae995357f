#pragma once
// What crosses the dispatch boundary: plain structs and pointers, never packet types or
// standard-library templates (they would be compiled with one ISA's flags and linked into
// another's code).
#include <cstddef>
#include <cstdint>

#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/precomputed.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

struct KernelTexture {
  const float* texels;  // SamplerTexture layout: (width + 1) x (height + 1)
  int width, height, stride;
  Wrap wrap;
  // The precomputed textures of the list (precomputed.hpp), each in its kind's slot (its
  // slot()); empty for the kinds the technique does not read.
#define HEIGHTMARCH_KERNEL_TEXTURE_SLOT(id, ...) TextureSlot id{};
  HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_KERNEL_TEXTURE_SLOT)
#undef HEIGHTMARCH_KERNEL_TEXTURE_SLOT
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

// One pointer per output of the list (hits.hpp); null where the caller holds no array for it.
struct KernelHits {
#define HEIGHTMARCH_KERNEL_HIT(name, type, ...) type* name = nullptr;
  HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_KERNEL_HIT)
#undef HEIGHTMARCH_KERNEL_HIT
};

// The arrays of a batch's hits (the exact pass's outputs, which no HitBuffers holds, left null).
inline KernelHits kernel_hits(HitBuffers& hits) {
  KernelHits out;
#define HEIGHTMARCH_KERNEL_HIT_OF(name, type, initial, writer, ...) \
  HEIGHTMARCH_IN_HITS_##writer(out.name = hits.name.data();)
  HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_KERNEL_HIT_OF)
#undef HEIGHTMARCH_KERNEL_HIT_OF
  return out;
}

struct KernelCounters {
  std::uint64_t lane_samples = 0;    // lanes that took a sample
  std::uint64_t packet_samples = 0;  // packet samples x width
};

// Traces rays [begin, end) (end - begin a multiple of the packet width) with one technique of one
// ISA, for one addressing mode of the texture.
using TraceRangeFn = void (*)(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&,
                              std::size_t begin, std::size_t end, KernelCounters&);

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
  // The exact reference's float pass (src/exact/exact_hits.cpp): per ray, where it settled the ray
  // (`settled`) the exact hit (uv, depth), found in double in the cell the pass stopped in; in
  // `clear_depth`, how far the path is certainly clear of the surface. In samples, the cells it
  // tested in float.
  TraceRangeFn exact_bound[kAddressingCount];
  TraceRangeFn compute_ceiling[kFilterCount][kAddressingCount];  // POM on register taps (benchmarks)
  // The naive port vectorised by the compiler (benchmarks), on a plain REPEAT DepthMap
  // (stride = width) instead of the sampler's layout.
  TraceRangeFn autovec_pom;
};

#define HEIGHTMARCH_ISA_KERNEL_TABLE(id, ...)                                                         \
  namespace isa_##id {                                                                                \
    const KernelTable& kernel_table();                                                                \
    void autovec_pom(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&, \
                     std::size_t, std::size_t, KernelCounters&); /* src/isa/autovec_<id>.cpp */       \
  }
HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_KERNEL_TABLE)
#undef HEIGHTMARCH_ISA_KERNEL_TABLE

// The table of a given ISA.
const KernelTable& kernel_table(Isa isa);

}  // namespace heightmarch
