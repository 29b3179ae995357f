#pragma once
// One ISA's kernel table: every technique of the registry (technique_list.hpp) x every addressing
// mode, each the packet loop below around the technique's kernel (its row's), beside the exact
// reference's float pass and the benchmarks' anchors. Included once per ISA by its generated
// translation unit (src/isa/kernels.cpp.in).
#include "all_techniques.hpp"  // generated: every header of src/kernels/techniques/
#include "exact/exact_bound.hpp"
#include "heightmarch/technique_list.hpp"
#include "kernels/roofline.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// A technique's kernel as a callable type (its registry row's kernel): k (the KernelContext) and a
// RayPacket in, a HitPacket out.
template <Technique T>
struct TechniqueKernel;
#define HEIGHTMARCH_TECHNIQUE_KERNEL(id, name, layered, refine, needs, writes, search, shape, kernel, ...) \
  template <>                                                                                               \
  struct TechniqueKernel<Technique::id> {                                                                   \
    template <class Context, class Ray>                                                                     \
    auto operator()(Context& k, const Ray& ray) const {                                                     \
      return kernel(k, ray);                                                                                \
    }                                                                                                       \
  };
HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_KERNEL)
#undef HEIGHTMARCH_TECHNIQUE_KERNEL

// The loop over packets: loads W rays, runs the technique, stores the hits. Flattened: every
// call inside is inlined, since a call in a kernel spills every vector register (all are
// caller-saved) and passes packets through memory; GCC otherwise left the sampler of the first
// and last samples out of line (measured: 11% of POM-32's time on AVX-512).
// Sanitizer builds skip it: their instrumented code is not timed, and flattening it multiplies
// their compile time.
#ifdef HEIGHTMARCH_SANITIZED
#define HEIGHTMARCH_FLATTEN
#else
#define HEIGHTMARCH_FLATTEN [[gnu::flatten]]
#endif
// An output's store: floats and counts as they are, flags as bytes.
template <int W>
void store_channel(vfloat<W> value, float* to) {
  value.store(to);
}
template <int W>
void store_channel(vint<W> value, std::uint32_t* to) {
  value.store(reinterpret_cast<std::int32_t*>(to));
}
template <int W>
void store_channel(vint<W> value, std::uint8_t* to) {
  store_bytes(value, to);
}

// Which outputs a kernel stores: a technique's (and the roofline's, the compute ceiling's) every
// output but the exact pass's; the exact reference's float pass its own too.
template <class Kernel>
inline constexpr bool kStoresExactPass = false;
constexpr bool stores(ChannelWriter writer, bool exact_pass) { return writer != ChannelWriter::exact_pass || exact_pass; }

template <int W, Addressing ADDRESSING, class Kernel, Taps TAPS = Taps::memory>
HEIGHTMARCH_FLATTEN void trace_packets(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                   const KernelHits& hits, std::size_t begin, std::size_t end,
                   KernelCounters& counters) {
  using F = vfloat<W>;
  KernelCounters local;  // not behind the output pointers (char aliases all)
  // Copies: the discard flags' char stores could alias the caller's structs, whose pointers
  // would then be reloaded after every store.
  const KernelRays in = rays;
  const KernelHits out = hits;
  KernelContext<W, ADDRESSING, TAPS> context(texture, params, local);
  const Kernel kernel;
  const vint<W> discard(params.discard ? 1 : 0);
  for (std::size_t i = begin; i < end; i += W) {
    const RayPacket<W> ray{F::load(in.tx + i), F::load(in.ty + i), F::load(in.vx + i), F::load(in.vy + i),
                           F::load(in.vz + i)};
    HitPacket<W> hit = kernel(context, ray);
    local.lane_samples += reduce_add(hit.samples);  // see KernelContext::count()
    const auto outside = (hit.u < F(0.0f)) | (hit.u > F(1.0f)) | (hit.v < F(0.0f)) | (hit.v > F(1.0f));
    hit.discarded = select(outside, discard, vint<W>(0));
#define HEIGHTMARCH_STORE_CHANNEL(name, type, initial, writer, ...) \
  if constexpr (stores(ChannelWriter::writer, kStoresExactPass<Kernel>)) store_channel(hit.name, out.name + i);
    HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_STORE_CHANNEL)
#undef HEIGHTMARCH_STORE_CHANNEL
  }
  counters.lane_samples += local.lane_samples;
  counters.packet_samples += local.packet_samples;
}

struct SamplerRooflineKernel {
  template <class Context, class Ray>
  auto operator()(Context& k, const Ray& ray) const {
    return sampler_roofline(k, ray);
  }
};

struct ExactBoundKernel {
  template <class Context, class Ray>
  auto operator()(Context& k, const Ray& ray) const {
    return maxmip_exact_bound(k, ray);
  }
};
template <>
inline constexpr bool kStoresExactPass<ExactBoundKernel> = true;

// The addressing modes in Addressing's order.
template <int W, class Kernel, Taps TAPS = Taps::memory>
constexpr void fill_addressing(TraceRangeFn (&row)[kAddressingCount]) {
  row[int(Addressing::repeat_pow2)] = &trace_packets<W, Addressing::repeat_pow2, Kernel, TAPS>;
  row[int(Addressing::repeat)] = &trace_packets<W, Addressing::repeat, Kernel, TAPS>;
  row[int(Addressing::clamp)] = &trace_packets<W, Addressing::clamp, Kernel, TAPS>;
}

// MARCH_W and WALK_W: the packet widths of the ISA's list (cmake/isa_list.cmake) for each
// KernelShape of the registry; tiles are padded to the wider, which the other divides.
template <int MARCH_W, int WALK_W>
constexpr KernelTable make_kernel_table() {
  constexpr int W = MARCH_W > WALK_W ? MARCH_W : WALK_W;
  static_assert(W % MARCH_W == 0 && W % WALK_W == 0, "tiles are padded to the wider packet");
  KernelTable table{};
  table.packet_width = W;
#define HEIGHTMARCH_TECHNIQUE_ROW(id, name, layered, refine, needs, writes, search, shape, ...)       \
  fill_addressing<shape == KernelShape::walk ? WALK_W : MARCH_W, TechniqueKernel<Technique::id>>( \
      table.technique[int(Technique::id)]);
  HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_ROW)
#undef HEIGHTMARCH_TECHNIQUE_ROW
  fill_addressing<MARCH_W, SamplerRooflineKernel>(table.sampler_roofline);
  fill_addressing<MARCH_W, ExactBoundKernel>(table.exact_bound);
  fill_addressing<MARCH_W, TechniqueKernel<Technique::pom>, Taps::registers>(table.compute_ceiling);
  table.autovec_pom = &autovec_pom;
  return table;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
