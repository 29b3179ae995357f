#pragma once
// One ISA's kernel table: every technique of the registry (technique_list.hpp) x every filter x
// every addressing mode, each the packet loop below around the technique's kernel (its row's), beside the
// exact reference's float pass and the benchmarks' anchors. Included once per ISA by its generated
// translation unit (src/isa/kernels.cpp.in).
#include "all_techniques.hpp"  // generated: every header of src/kernels/techniques/
#include "exact/exact_bound.hpp"
#include "heightmarch/technique_list.hpp"
#include "kernels/pyramid_walk.hpp"
#include "kernels/roofline.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// A technique's kernel as a callable type (its registry row's kernel): k (the KernelContext) and a
// RayPacket in (and a walk's PyramidWalk), a HitPacket out; a walk's first step (WalkSteps) beside.
template <Technique T>
struct TechniqueKernel;
#define HEIGHTMARCH_TECHNIQUE_KERNEL(id, name, layered, refine, needs, writes, search, shape, kernel, ...) \
  template <>                                                                                              \
  struct TechniqueKernel<Technique::id> : WalkSteps<Technique::id> {                                       \
    template <class Context, class Ray, class... Walk>                                                     \
    auto operator()(Context& k, const Ray& ray, const Walk&... walk) const {                               \
      return kernel(k, ray, walk...);                                                                      \
    }                                                                                                      \
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
template <int W>
RayPacket<W> load_rays(const KernelRays& in, std::size_t i) {
  using F = vfloat<W>;
  return {F::load(in.tx + i), F::load(in.ty + i), F::load(in.vx + i), F::load(in.vy + i), F::load(in.vz + i)};
}

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
constexpr bool stores(ChannelWriter writer, bool exact_pass) {
  return writer != ChannelWriter::exact_pass || exact_pass;
}

// Rays i .. i + W - 1's outputs, the discard flags set here, and their samples counted.
template <class Kernel, int W>
void store_hits(HitPacket<W> hit, const KernelHits& out, std::size_t i, vint<W> discard,
                KernelCounters& local) {
  using F = vfloat<W>;
  local.lane_samples += reduce_add(hit.samples);  // see KernelContext::count()
  const auto outside = (hit.u < F(0.0f)) | (hit.u > F(1.0f)) | (hit.v < F(0.0f)) | (hit.v > F(1.0f));
  hit.discarded = select(outside, discard, vint<W>(0));
#define HEIGHTMARCH_STORE_CHANNEL(name, type, initial, writer, ...)      \
  if constexpr (stores(ChannelWriter::writer, kStoresExactPass<Kernel>)) \
    store_channel(hit.name, out.name + i);
  HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_STORE_CHANNEL)
#undef HEIGHTMARCH_STORE_CHANNEL
}

template <int W, Addressing ADDRESSING, class Kernel, Taps TAPS = Taps::memory,
          Filter FILTER = Filter::bilinear>
HEIGHTMARCH_FLATTEN void trace_packets(const KernelTexture& texture, const KernelParams& params,
                                       const KernelRays& rays, const KernelHits& hits, std::size_t begin,
                                       std::size_t end, KernelCounters& counters) {
  KernelCounters local;  // not behind the output pointers (char aliases all)
  // Copies: the discard flags' char stores could alias the caller's structs, whose pointers
  // would then be reloaded after every store.
  const KernelRays in = rays;
  const KernelHits out = hits;
  KernelContext<W, ADDRESSING, TAPS, FILTER> context(texture, params, local);
  const Kernel kernel;
  const vint<W> discard(params.discard ? 1 : 0);
  for (std::size_t i = begin; i < end; i += W) {
    if constexpr (FILTER == Filter::trilinear) {
      using F = vfloat<W>;
      context.set_footprint(F::load(in.du_dx + i), F::load(in.dv_dx + i), F::load(in.du_dy + i),
                            F::load(in.dv_dy + i));
    }
    store_hits<Kernel>(kernel(context, load_rays<W>(in, i)), out, i, discard, local);
  }
  counters.lane_samples += local.lane_samples;
  counters.packet_samples += local.packet_samples;
}

// The loop of a walk's kernel (KernelShape::walk, the exact reference's float pass): the range's
// rays are queued up to kWalkQueueRays at a time and walked (kernels/pyramid_walk.hpp), their events
// taken EVENT_LANES lanes at a time; then each packet's hits are made from its rays' walks.
template <int W, Addressing ADDRESSING, class Kernel, int EVENT_LANES>
HEIGHTMARCH_FLATTEN void trace_walks(const KernelTexture& texture, const KernelParams& params,
                                     const KernelRays& rays, const KernelHits& hits, std::size_t begin,
                                     std::size_t end, KernelCounters& counters) {
  KernelCounters local;  // as trace_packets
  const KernelRays in = rays;
  const KernelHits out = hits;
  KernelContext<W, ADDRESSING> context(texture, params, local);
  const Kernel kernel;
  const vint<W> discard(params.discard ? 1 : 0);
  PyramidWalker<Kernel::kConservative, W, ADDRESSING, EVENT_LANES> walker(context);
  WalkQueue queue;  // 90 KB with the outcomes: within every thread's stack
  WalkOutcomes outcomes;
  for (std::size_t first = begin; first < end; first += kWalkQueueRays) {
    const int n = int(std::min<std::size_t>(kWalkQueueRays, end - first));
    for (int i = 0; i < n; i += W) kernel.queue(context, load_rays<W>(in, first + i), queue, i);
    walker.run(queue, n, outcomes);
    for (int i = 0; i < n; i += W)
      store_hits<Kernel>(kernel(context, load_rays<W>(in, first + i),
                                PyramidWalk<W>::template at<Kernel::kConservative>(outcomes, i)),
                         out, first + i, discard, local);
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

// A walk's kernel, as TechniqueKernel<Technique::maxmip>.
struct ExactBoundKernel {
  static constexpr bool kConservative = true;
  template <class Context, class Ray>
  void queue(const Context& k, const Ray& ray, WalkQueue& queue, int i) const {
    queue_exact_bound(k, ray, queue, i);
  }
  template <class Context, class Ray, class Walk>
  auto operator()(Context& k, const Ray& ray, const Walk& walk) const {
    return maxmip_exact_bound(k, ray, walk);
  }
};
template <>
inline constexpr bool kStoresExactPass<ExactBoundKernel> = true;

// The addressing modes in Addressing's order, each the packet loop of its kernel's shape.
template <int W, class Kernel, Taps TAPS = Taps::memory, KernelShape SHAPE = KernelShape::march,
          Filter FILTER = Filter::bilinear, int EVENT_LANES = 1>
constexpr void fill_addressing(TraceRangeFn (&row)[kAddressingCount]) {
  if constexpr (SHAPE == KernelShape::walk) {
    row[int(Addressing::repeat_pow2)] = &trace_walks<W, Addressing::repeat_pow2, Kernel, EVENT_LANES>;
    row[int(Addressing::repeat)] = &trace_walks<W, Addressing::repeat, Kernel, EVENT_LANES>;
    row[int(Addressing::clamp)] = &trace_walks<W, Addressing::clamp, Kernel, EVENT_LANES>;
  } else {
    row[int(Addressing::repeat_pow2)] = &trace_packets<W, Addressing::repeat_pow2, Kernel, TAPS, FILTER>;
    row[int(Addressing::repeat)] = &trace_packets<W, Addressing::repeat, Kernel, TAPS, FILTER>;
    row[int(Addressing::clamp)] = &trace_packets<W, Addressing::clamp, Kernel, TAPS, FILTER>;
  }
}

// Both filters' rows. A walk reads texels, never a filtered sample (maxmip's walk and the patch
// it solves, texelFetch in GLSL): its one instantiation serves both.
template <int W, class Kernel, Taps TAPS = Taps::memory, KernelShape SHAPE = KernelShape::march,
          int EVENT_LANES = 1>
constexpr void fill_filters(TraceRangeFn (&rows)[kFilterCount][kAddressingCount]) {
  fill_addressing<W, Kernel, TAPS, SHAPE, Filter::bilinear, EVENT_LANES>(rows[int(Filter::bilinear)]);
  fill_addressing<W, Kernel, TAPS, SHAPE, filter_read(SHAPE, Filter::trilinear), EVENT_LANES>(
      rows[int(Filter::trilinear)]);
}

// MARCH_W and WALK_W: the packet widths of the ISA's list (cmake/isa_list.cmake) for each
// KernelShape of the registry; tiles are padded to the wider, which the other divides.
// WALK_EVENT_LANES: how many of a walk's lanes wait before its events are taken (the list's too).
template <int MARCH_W, int WALK_W, int WALK_EVENT_LANES>
constexpr KernelTable make_kernel_table() {
  constexpr int W = MARCH_W > WALK_W ? MARCH_W : WALK_W;
  static_assert(W % MARCH_W == 0 && W % WALK_W == 0, "tiles are padded to the wider packet");
  KernelTable table{};
  table.packet_width = W;
#define HEIGHTMARCH_TECHNIQUE_ROW(id, name, layered, refine, needs, writes, search, shape, ...)             \
  fill_filters<shape == KernelShape::walk ? WALK_W : MARCH_W, TechniqueKernel<Technique::id>, Taps::memory, \
               shape, WALK_EVENT_LANES>(table.technique[int(Technique::id)]);
  HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_ROW)
#undef HEIGHTMARCH_TECHNIQUE_ROW
  fill_filters<MARCH_W, SamplerRooflineKernel>(table.sampler_roofline);
  fill_addressing<WALK_W, ExactBoundKernel, Taps::memory, KernelShape::walk, Filter::bilinear,
                  WALK_EVENT_LANES>(table.exact_bound);  // the level-0 surface
  fill_filters<MARCH_W, TechniqueKernel<Technique::pom>, Taps::registers>(table.compute_ceiling);
  table.autovec_pom = &autovec_pom;
  return table;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
