// The naive POM port (naive_port.cpp) as an engineer who does not hand-write SIMD would write it
// with Google Highway: the same lines over Lanes(d) rays at a time, the tutorial's loop condition
// a mask, its branches IfThenElse, the taps read with GatherIndex. Compiled once per target that
// Highway builds for (foreach_target.h); each ISA of cmake/isa_list.cmake runs the entry of its
// Highway target in Highway's dispatch table (HWY_DYNAMIC_DISPATCH would pick the best one the
// CPU runs). Only the plain structs of kernels/kernel_abi.hpp cross that boundary.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "baselines/highway_port.cpp"
#include <hwy/foreach_target.h>  // includes this file once per target
#include <hwy/highway.h>

#include "kernels/kernel_abi.hpp"

HWY_BEFORE_NAMESPACE();
namespace heightmarch {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most 16 lanes, so that every tile (a multiple of kRayAlignment rays) is whole vectors.
using PortTag = hn::CappedTag<float, 16>;
using Vf = hn::Vec<PortTag>;
using Vi = hn::Vec<hn::RebindToSigned<PortTag>>;

Vf Mix(Vf x, Vf y, Vf a) {  // glm::mix
  return hn::Add(hn::Mul(x, hn::Sub(hn::Set(PortTag(), 1.0f), a)), hn::Mul(y, a));
}

// GL_REPEAT of an integer-valued texel index, i mod n, as the auto-vectorised port wraps it.
Vi Wrap(Vf i, Vf n, Vf inv_n) {
  const PortTag d;
  Vf r = hn::Sub(i, hn::Mul(n, hn::Floor(hn::Mul(i, inv_n))));
  r = hn::IfThenElse(hn::Lt(r, hn::Zero(d)), hn::Add(r, n), r);
  r = hn::IfThenElse(hn::Ge(r, n), hn::Sub(r, n), r);
  return hn::ConvertTo(hn::RebindToSigned<PortTag>(), r);
}

// texture(depthMap, uv).r with GL_LINEAR and GL_REPEAT on a plain depth map (stride = width).
Vf Sample(const KernelTexture& t, Vf u, Vf v) {
  const PortTag d;
  const hn::RebindToSigned<PortTag> di;
  const Vf w = hn::Set(d, float(t.width)), h = hn::Set(d, float(t.height)), half = hn::Set(d, 0.5f);
  const Vf inv_w = hn::Set(d, 1.0f / float(t.width)), inv_h = hn::Set(d, 1.0f / float(t.height));
  const Vf x = hn::Sub(hn::Mul(u, w), half), y = hn::Sub(hn::Mul(v, h), half);
  const Vf x0 = hn::Floor(x), y0 = hn::Floor(y);
  const Vf fx = hn::Sub(x, x0), fy = hn::Sub(y, y0);
  const Vf one = hn::Set(d, 1.0f);
  const Vi i0 = Wrap(x0, w, inv_w), i1 = Wrap(hn::Add(x0, one), w, inv_w);
  const Vi row0 = hn::Mul(Wrap(y0, h, inv_h), hn::Set(di, t.stride));
  const Vi row1 = hn::Mul(Wrap(hn::Add(y0, one), h, inv_h), hn::Set(di, t.stride));
  const Vf a = hn::GatherIndex(d, t.texels, hn::Add(row0, i0)),
           b = hn::GatherIndex(d, t.texels, hn::Add(row0, i1));
  const Vf c = hn::GatherIndex(d, t.texels, hn::Add(row1, i0)),
           e = hn::GatherIndex(d, t.texels, hn::Add(row1, i1));
  return Mix(Mix(a, b, fx), Mix(c, e, fx), fy);
}

// Traces rays [begin, end): the tutorial's POM with its loop bound, writing u, v and samples as
// the naive port does.
void TracePom(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
              const KernelHits& hits, std::size_t begin, std::size_t end, KernelCounters& counters) {
  const PortTag d;
  const hn::RebindToSigned<PortTag> di;
  const std::size_t n = hn::Lanes(d);
  const Vf min_layers = hn::Set(d, params.min_layers), max_layers = hn::Set(d, params.max_layers);
  const Vf height_scale = hn::Set(d, params.scale), one = hn::Set(d, 1.0f);
  std::uint64_t taken = 0;
  for (std::size_t i = begin; i < end; i += n) {
    const Vf vx = hn::LoadU(d, rays.vx + i), vy = hn::LoadU(d, rays.vy + i), vz = hn::LoadU(d, rays.vz + i);
    const Vf num_layers = Mix(max_layers, min_layers, hn::Abs(vz));  // |dot((0, 0, 1), V)|
    const Vf layer_depth = hn::Div(one, num_layers);
    const Vf du = hn::Div(hn::Mul(hn::Div(vx, vz), height_scale), num_layers);
    const Vf dv = hn::Div(hn::Mul(hn::Div(vy, vz), height_scale), num_layers);
    Vf u = hn::LoadU(d, rays.tx + i), v = hn::LoadU(d, rays.ty + i);
    Vf current_layer_depth = hn::Zero(d);
    Vf depth_map_value = Sample(texture, u, v);
    Vi samples = hn::Set(di, 1);
    const Vi bound = hn::Add(hn::ConvertTo(di, hn::Ceil(num_layers)), hn::Set(di, 1));
    auto going =
        hn::And(hn::Lt(current_layer_depth, depth_map_value), hn::RebindMask(d, hn::Lt(hn::Zero(di), bound)));
    // The tutorial's while loop, with the loop bound of docs/techniques.md.
    for (int step = 1; !hn::AllFalse(d, going); ++step) {
      const Vf next_u = hn::Sub(u, du), next_v = hn::Sub(v, dv);
      const Vf next_value = Sample(texture, next_u, next_v);
      const Vf next_depth = hn::Add(current_layer_depth, layer_depth);
      u = hn::IfThenElse(going, next_u, u);
      v = hn::IfThenElse(going, next_v, v);
      depth_map_value = hn::IfThenElse(going, next_value, depth_map_value);
      current_layer_depth = hn::IfThenElse(going, next_depth, current_layer_depth);
      samples = hn::Add(samples, hn::IfThenElseZero(hn::RebindMask(di, going), hn::Set(di, 1)));
      going = hn::And(hn::And(going, hn::Lt(next_depth, next_value)),
                      hn::RebindMask(d, hn::Lt(hn::Set(di, step), bound)));
    }
    const Vf prev_u = hn::Add(u, du), prev_v = hn::Add(v, dv);
    const Vf after_depth = hn::Sub(depth_map_value, current_layer_depth);
    const Vf before_depth =
        hn::Add(hn::Sub(Sample(texture, prev_u, prev_v), current_layer_depth), layer_depth);
    const Vf weight = hn::Div(after_depth, hn::Sub(after_depth, before_depth));
    hn::StoreU(hn::Add(hn::Mul(prev_u, weight), hn::Mul(u, hn::Sub(one, weight))), d, hits.u + i);
    hn::StoreU(hn::Add(hn::Mul(prev_v, weight), hn::Mul(v, hn::Sub(one, weight))), d, hits.v + i);
    samples = hn::Add(samples, hn::Set(di, 1));
    hn::StoreU(samples, di, reinterpret_cast<std::int32_t*>(hits.samples + i));
    taken += std::uint64_t(hn::GetLane(hn::SumOfLanes(di, samples)));
  }
  counters.lane_samples += taken;
  counters.packet_samples += taken;
}

}  // namespace HWY_NAMESPACE
}  // namespace heightmarch
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "baselines/highway_port.hpp"
#include "highway_targets.hpp"  // generated from cmake/isa_list.cmake

namespace heightmarch {

HWY_EXPORT(TracePom);

int highway_dispatch_entry(Isa isa) {
  std::int64_t targets = 0;
#define HEIGHTMARCH_HIGHWAY_TARGET(id, highway_targets) \
  if (isa == Isa::id) targets = highway_targets;
  HEIGHTMARCH_HIGHWAY_TARGETS(HEIGHTMARCH_HIGHWAY_TARGET)
#undef HEIGHTMARCH_HIGHWAY_TARGET
  // Compiled by Highway, run by this CPU (Highway's check and ours).
  const std::int64_t target = targets & HWY_TARGETS & hwy::SupportedTargets();
  if (target == 0 || !cpu_supports(isa)) return -1;
  // The target's entry of Highway's dispatch table, as ChosenTarget::GetIndex() finds the best
  // one's (the last entry is its portable fallback, HWY_EMU128 or HWY_SCALAR).
  const std::int64_t bit =
      target & (HWY_EMU128 | HWY_SCALAR) ? HWY_CHOSEN_TARGET_MASK_SCALAR : HWY_CHOSEN_TARGET_SHIFT(target);
  return int(hwy::Num0BitsBelowLS1Bit_Nonzero64(std::uint64_t(bit)));
}

TraceRangeFn highway_kernel(Isa isa) {
  const int entry = highway_dispatch_entry(isa);
  return entry < 0 ? nullptr : HWY_DISPATCH_TABLE(TracePom)[entry];
}

}  // namespace heightmarch
#endif  // HWY_ONCE
