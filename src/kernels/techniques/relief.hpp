#pragma once
// Relief mapping: steep parallax, then a binary search between the last two layers
// (the "Parallax Occlusion Mapping in GLSL" tutorial's loop: the step halves before each sample, the last
// sample only moves the point).
#include "kernels/layer_march.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> relief(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  LayerMarch<W> m = march_layers<false>(k, ray);
  F delta_u = m.delta_u / F(2.0f);
  F delta_v = m.delta_v / F(2.0f);
  F delta_depth = m.layer_depth / F(2.0f);
  F u = m.u + delta_u;
  F v = m.v + delta_v;
  F depth = m.current_layer_depth - delta_depth;
  for (int i = 0; i < k.params.refine_steps; ++i) {
    delta_u = delta_u / F(2.0f);
    delta_v = delta_v / F(2.0f);
    delta_depth = delta_depth / F(2.0f);
    const F depth_map_value = k.sample(u, v, vbool<W>::all_true(), m.samples);
    const vbool<W> below = depth_map_value > depth;
    u = select(below, u - delta_u, u + delta_u);
    v = select(below, v - delta_v, v + delta_v);
    depth = select(below, depth + delta_depth, depth - delta_depth);
  }
  HitPacket<W> hit;
  hit.u = u;
  hit.v = v;
  hit.depth = depth;
  hit.samples = m.samples;
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
