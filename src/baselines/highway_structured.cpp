// The hand-written POM (src/kernels/techniques/pom.hpp, the layer march and the sampler on
// packets) written a second time on Google Highway's portable ops, as an engineer who knows the
// structure but not the ISAs would: the same packets of rays in their 8 x 2 pixel blocks, the same
// march (every lane advances, the loop bound tested only from the packet's smallest bound on),
// the same bilinear arithmetic in the same order, and the taps read from registers where a
// packet's taps lie in a window of texel rows, else by gathers of texel pairs. Its hits equal the
// hand-written kernel's bit for bit. Compiled once per target Highway builds (foreach_target.h),
// run at each ISA's Highway target (cmake/isa_list.cmake) as highway_port.cpp's port is.
//
// What Highway 1.0's portable ops allow, per width, against the hand-written fetch_taps:
// - 8 lanes (HWY_AVX2): lane 0's texel row and the next, 8 columns, picked by TableLookupLanes:
//   the hand-written AVX2 path, op for op.
// - 16 lanes (HWY_AVX3): no two-table lookup (AVX-512's vpermt2ps) among the portable ops, so
//   a window of 8 columns x 2 rows in one register per tap row, where the hand-written kernel
//   reads 8 x 5 rows with two-table permutes; more packets fall back to the gathers.
// - 4 lanes (HWY_SSE4, HWY_EMU128): gathers of texel pairs (Highway emulates them with scalar
//   loads, as the hand-written SSE4.2 path reads pairs with 64-bit loads).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "baselines/highway_structured.cpp"
#include <hwy/foreach_target.h>  // includes this file once per target
#include <hwy/highway.h>

#include <algorithm>

#include "kernels/kernel_abi.hpp"

HWY_BEFORE_NAMESPACE();
namespace heightmarch {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most 16 lanes, so that every tile (a multiple of kRayAlignment rays) is whole vectors.
using StructuredTag = hn::CappedTag<float, 16>;
using Vs = hn::Vec<StructuredTag>;
using Vsi = hn::Vec<hn::RebindToSigned<StructuredTag>>;
using Ms = hn::Mask<StructuredTag>;

// base[index] and base[index + 1] per lane: texel pairs gathered as 64-bit lanes, then
// deinterleaved (the hand-written gather_pairs); single texels on HWY_SCALAR, whose one lane has
// no halves.
template <class D>
HWY_INLINE void GatherPairs(D d, const float* base, hn::Vec<hn::RebindToSigned<D>> index, hn::Vec<D>& first,
                            hn::Vec<D>& second) {
#if HWY_TARGET == HWY_SCALAR
  first = hn::GatherIndex(d, base, index);
  second = hn::GatherIndex(d, base + 1, index);
#else
  const hn::Repartition<std::uint64_t, D> d64;  // half as many lanes, of pairs
  const hn::Repartition<std::int64_t, D> di64;
  const hn::Half<hn::RebindToSigned<D>> dhi;
  const auto* pairs = reinterpret_cast<const std::uint64_t*>(base);
  const auto offsets = [&](auto half) { return hn::ShiftLeft<2>(hn::PromoteTo(di64, half)); };  // bytes
  const auto lo = hn::BitCast(d, hn::GatherOffset(d64, pairs, offsets(hn::LowerHalf(dhi, index))));
  const auto hi = hn::BitCast(d, hn::GatherOffset(d64, pairs, offsets(hn::UpperHalf(dhi, index))));
  first = hn::ConcatEven(d, hi, lo);
  second = hn::ConcatOdd(d, hi, lo);
#endif
}

// Each lane's taps from registers holding the window: t00 and t10 at entries `at` and at + 1 of
// `top`, t01 and t11 at the same entries of `below` (the window one row down).
template <class D>
HWY_INLINE void PickTaps(D d, hn::Vec<D> top, hn::Vec<D> below, hn::Vec<hn::RebindToSigned<D>> at,
                         hn::Vec<D>& t00, hn::Vec<D>& t10, hn::Vec<D>& t01, hn::Vec<D>& t11) {
  const auto left = hn::IndicesFromVec(d, at);
  const auto right = hn::IndicesFromVec(d, hn::Add(at, hn::Set(hn::RebindToSigned<D>(), 1)));
  t00 = hn::TableLookupLanes(top, left);
  t10 = hn::TableLookupLanes(top, right);
  t01 = hn::TableLookupLanes(below, left);
  t11 = hn::TableLookupLanes(below, right);
}

// The four taps of each lane (fetch_taps): from a window of rows where every lane's taps lie in
// it, else by gathers.
template <class D>
HWY_INLINE void FetchTaps(D d, const KernelTexture& t, hn::Vec<hn::RebindToSigned<D>> ix,
                          hn::Vec<hn::RebindToSigned<D>> iy, hn::Vec<D>& t00, hn::Vec<D>& t10,
                          hn::Vec<D>& t01, hn::Vec<D>& t11) {
  using VI = hn::Vec<hn::RebindToSigned<D>>;
  const hn::RebindToSigned<D> di;
  if constexpr (hn::MaxLanes(d) == 8) {
    // Lane 0's row and the next, 8 columns from lane 0's (moved left where the row would end).
    const std::int32_t x0 = std::min(hn::GetLane(ix), t.stride - 8);
    const std::int32_t y0 = hn::GetLane(iy);
    const VI dx = hn::Sub(ix, hn::Set(di, x0));
    const auto inside =
        hn::And(hn::Eq(iy, hn::Set(di, y0)),
                hn::And(hn::Lt(hn::Set(di, -1), dx), hn::Lt(dx, hn::Set(di, 7))));  // 0 <= dx <= 6
    if (t.stride >= 8 && hn::AllTrue(di, inside)) {
      const float* row = t.texels + std::ptrdiff_t(y0) * t.stride + x0;
      PickTaps(d, hn::LoadU(d, row), hn::LoadU(d, row + t.stride), dx, t00, t10, t01, t11);
      return;
    }
  }
#if HWY_TARGET != HWY_SCALAR
  if constexpr (hn::MaxLanes(d) == 16) {
    // Columns x0 .. x0 + 7 and rows y0 .. y0 + 2 from the lanes' smallest: the taps' rows two
    // at a time in one register of 16 (entry 8 dy + dx).
    const std::int32_t x0 = std::min(hn::GetLane(hn::MinOfLanes(di, ix)), t.stride - 8);
    const std::int32_t y0 = hn::GetLane(hn::MinOfLanes(di, iy));
    const VI dx = hn::Sub(ix, hn::Set(di, x0)), dy = hn::Sub(iy, hn::Set(di, y0));
    const auto inside =
        hn::And(hn::And(hn::Lt(hn::Set(di, -1), dx), hn::Lt(dx, hn::Set(di, 7))), hn::Lt(dy, hn::Set(di, 2)));
    if (x0 >= 0 && t.stride >= 8 && y0 + 3 <= t.height + 1 && hn::AllTrue(di, inside)) {
      const hn::Half<D> dh;
      const float* row = t.texels + std::ptrdiff_t(y0) * t.stride + x0;
      const auto two_rows = [&](int r) {
        return hn::Combine(d, hn::LoadU(dh, row + std::ptrdiff_t(r + 1) * t.stride),
                           hn::LoadU(dh, row + std::ptrdiff_t(r) * t.stride));
      };
      PickTaps(d, two_rows(0), two_rows(1), hn::Add(hn::ShiftLeft<3>(dy), dx), t00, t10, t01, t11);
      return;
    }
  }
#endif
  const VI index = hn::Add(hn::Mul(iy, hn::Set(di, t.stride)), ix);
  GatherPairs(d, t.texels, index, t00, t10);
  GatherPairs(d, t.texels + t.stride, index, t01, t11);
}

// The bilinear sample of docs/conventions.md on a REPEAT power-of-two map (PacketSampler's).
// Internal: highway_port.cpp has a Sample of its own in the same namespace. Inlined, as the
// hand-written sampler is: a call in the march would spill every vector register.
static HWY_INLINE Vs Sample(const KernelTexture& t, Vs u, Vs v) {
  const StructuredTag d;
  const hn::RebindToSigned<StructuredTag> di;
  const Vs x = hn::Sub(hn::Mul(u, hn::Set(d, float(t.width))), hn::Set(d, 0.5f));
  const Vs y = hn::Sub(hn::Mul(v, hn::Set(d, float(t.height))), hn::Set(d, 0.5f));
  const Vs x0 = hn::Floor(x), y0 = hn::Floor(y);
  const Vs fx = hn::Sub(x, x0), fy = hn::Sub(y, y0);
  const Vsi ix = hn::And(hn::ConvertTo(di, x0), hn::Set(di, t.width - 1));
  const Vsi iy = hn::And(hn::ConvertTo(di, y0), hn::Set(di, t.height - 1));
  Vs t00, t10, t01, t11;
  FetchTaps(d, t, ix, iy, t00, t10, t01, t11);
  const Vs top = hn::Add(t00, hn::Mul(fx, hn::Sub(t10, t00)));
  const Vs bottom = hn::Add(t01, hn::Mul(fx, hn::Sub(t11, t01)));
  return hn::Add(top, hn::Mul(fy, hn::Sub(bottom, top)));
}

// Traces rays [begin, end) with POM as src/kernels/techniques/pom.hpp does, on a REPEAT map of
// power-of-two sides in the sampler's layout; writes what the technique kernels write.
void TracePomStructured(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                        const KernelHits& hits, std::size_t begin, std::size_t end,
                        KernelCounters& counters) {
  const StructuredTag d;
  const hn::RebindToSigned<StructuredTag> di;
  const std::size_t n = hn::Lanes(d);
  const Vs zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const Vsi count_one = hn::Set(di, 1);
  const int max_step_bound = int(params.max_layers) + 2;
  KernelCounters local;
  for (std::size_t i = begin; i < end; i += n) {
    const Vs tx = hn::LoadU(d, rays.tx + i), ty = hn::LoadU(d, rays.ty + i);
    const Vs vx = hn::LoadU(d, rays.vx + i), vy = hn::LoadU(d, rays.vy + i), vz = hn::LoadU(d, rays.vz + i);
    // heightmarch::layer_count (technique.hpp).
    Vs num_layers = hn::Set(d, params.max_layers);
    if (params.min_layers != params.max_layers) {
      const Vs a = hn::Abs(vz);
      num_layers = hn::Add(hn::Mul(hn::Set(d, params.max_layers), hn::Sub(one, a)),
                           hn::Mul(hn::Set(d, params.min_layers), a));
    }
    const Vs layer_depth = hn::Div(one, num_layers);
    const Vs p_x = hn::Mul(hn::Div(vx, vz), hn::Set(d, params.scale));
    const Vs p_y = hn::Mul(hn::Div(vy, vz), hn::Set(d, params.scale));
    const Vs delta_u = hn::Div(p_x, num_layers), delta_v = hn::Div(p_y, num_layers);
    // march_layers (src/kernels/layer_march.hpp): every lane advances; the lanes still above the
    // surface keep their last sample.
    Vs u = tx, v = ty, current_layer_depth = zero;
    Vs last_u = u, last_v = v, last_value = Sample(texture, u, v), last_layer_depth = zero;
    Vsi samples = count_one;
    const Vsi bound = hn::Add(hn::ConvertTo(di, hn::Ceil(num_layers)), count_one);
    Ms active = hn::Lt(current_layer_depth, last_value);
    int step = 1;
    const auto layer_step = [&](bool bounded) {
      u = hn::Sub(u, delta_u);
      v = hn::Sub(v, delta_v);
      const Vs depth_map_value = Sample(texture, u, v);
      samples = hn::IfThenElse(hn::RebindMask(di, active), hn::Add(samples, count_one), samples);
      current_layer_depth = hn::Add(current_layer_depth, layer_depth);
      last_u = hn::IfThenElse(active, u, last_u);
      last_v = hn::IfThenElse(active, v, last_v);
      last_value = hn::IfThenElse(active, depth_map_value, last_value);
      last_layer_depth = hn::IfThenElse(active, current_layer_depth, last_layer_depth);
      active = hn::And(active, hn::Lt(current_layer_depth, depth_map_value));
      if (bounded) active = hn::And(active, hn::RebindMask(d, hn::Lt(hn::Set(di, step), bound)));
    };
    // Up to the packet's smallest bound every lane passes its bound test: those steps skip it.
    const int unbounded_steps = hn::GetLane(hn::MinOfLanes(di, bound)) - 1;
    for (; step <= unbounded_steps && !hn::AllFalse(d, active); ++step) layer_step(false);
    for (; step <= max_step_bound && !hn::AllFalse(d, active); ++step) layer_step(true);
    // pom(): the previous layer read again and the tutorial's interpolation.
    const Vs prev_u = hn::Add(last_u, delta_u), prev_v = hn::Add(last_v, delta_v);
    const Vs after_depth = hn::Sub(last_value, last_layer_depth);
    const Vs before_depth = hn::Add(hn::Sub(Sample(texture, prev_u, prev_v), last_layer_depth), layer_depth);
    samples = hn::Add(samples, count_one);
    local.packet_samples += std::uint64_t(step + 1) * n;  // the first sample, the steps, the re-read
    const Vs denominator = hn::Sub(after_depth, before_depth);
    const Vs weight = hn::IfThenElse(hn::Ne(denominator, zero), hn::Div(after_depth, denominator), zero);
    const Vs one_minus_weight = hn::Sub(one, weight);
    const Vs hit_u = hn::Add(hn::Mul(prev_u, weight), hn::Mul(last_u, one_minus_weight));
    const Vs hit_v = hn::Add(hn::Mul(prev_v, weight), hn::Mul(last_v, one_minus_weight));
    hn::StoreU(hit_u, d, hits.u + i);
    hn::StoreU(hit_v, d, hits.v + i);
    hn::StoreU(hn::Add(hn::Mul(hn::Sub(last_layer_depth, layer_depth), weight),
                       hn::Mul(last_layer_depth, one_minus_weight)),
               d, hits.depth + i);
    hn::StoreU(one, d, hits.shadow + i);
    hn::StoreU(samples, di, reinterpret_cast<std::int32_t*>(hits.samples + i));
    local.lane_samples += std::uint64_t(hn::GetLane(hn::SumOfLanes(di, samples)));
    const Ms outside = hn::Or(hn::Or(hn::Lt(hit_u, zero), hn::Gt(hit_u, one)),
                              hn::Or(hn::Lt(hit_v, zero), hn::Gt(hit_v, one)));
    alignas(64) std::int32_t discarded[16];
    hn::Store(hn::IfThenElseZero(hn::RebindMask(di, outside), hn::Set(di, params.discard ? 1 : 0)), di,
              discarded);
    for (std::size_t lane = 0; lane < n; ++lane) hits.discarded[i + lane] = std::uint8_t(discarded[lane]);
  }
  counters.lane_samples += local.lane_samples;
  counters.packet_samples += local.packet_samples;
}

}  // namespace HWY_NAMESPACE
}  // namespace heightmarch
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "baselines/highway_port.hpp"

namespace heightmarch {

HWY_EXPORT(TracePomStructured);

TraceRangeFn highway_structured_kernel(Isa isa) {
  const int entry = highway_dispatch_entry(isa);
  return entry < 0 ? nullptr : HWY_DISPATCH_TABLE(TracePomStructured)[entry];
}

}  // namespace heightmarch
#endif  // HWY_ONCE
