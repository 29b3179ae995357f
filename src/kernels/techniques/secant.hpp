#pragma once
// Secant (interval) mapping: steep parallax, then regula falsi between the last layer above the
// surface and the first below it. Each iteration samples at the bracket's linear interpolation
// (POM's weight) and keeps the side where the ray's depth minus the surface's changes sign; the
// result is one more interpolation without a sample. With no iterations it is POM.
#include "kernels/layer_march.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> secant(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  using B = vbool<W>;
  LayerMarch<W> m = march_layers<false>(k, ray);
  // The bracket: a above the surface (gap = D - depth > 0), b at or below it (gap <= 0).
  F a_u = m.u + m.delta_u, a_v = m.v + m.delta_v, a_depth = m.current_layer_depth - m.layer_depth;
  F b_u = m.u, b_v = m.v, b_depth = m.current_layer_depth;
  // Both gaps written as POM writes them, so that no iterations give POM bit for bit.
  F a_gap = k.sample(a_u, a_v, B::all_true(), m.samples) - m.current_layer_depth + m.layer_depth;
  F b_gap = m.depth_map_value - m.current_layer_depth;
  // POM's weight of a; a vanishing denominator keeps b, as POM keeps its layer.
  const auto weight_of_a = [](F a_gap, F b_gap) {
    const F denominator = b_gap - a_gap;
    return select(denominator != F(0.0f), b_gap / denominator, F(0.0f));
  };
  for (int i = 0; i < k.params.refine_steps; ++i) {
    const F w = weight_of_a(a_gap, b_gap);
    const F one_minus_w = F(1.0f) - w;
    const F u = a_u * w + b_u * one_minus_w;
    const F v = a_v * w + b_v * one_minus_w;
    const F depth = a_depth * w + b_depth * one_minus_w;
    const F gap = k.sample(u, v, B::all_true(), m.samples) - depth;
    const B above = gap > F(0.0f);
    a_u = select(above, u, a_u);
    a_v = select(above, v, a_v);
    a_depth = select(above, depth, a_depth);
    a_gap = select(above, gap, a_gap);
    b_u = select(above, b_u, u);
    b_v = select(above, b_v, v);
    b_depth = select(above, b_depth, depth);
    b_gap = select(above, b_gap, gap);
  }
  const F w = weight_of_a(a_gap, b_gap);
  const F one_minus_w = F(1.0f) - w;
  HitPacket<W> hit;
  hit.u = a_u * w + b_u * one_minus_w;
  hit.v = a_v * w + b_v * one_minus_w;
  hit.depth = a_depth * w + b_depth * one_minus_w;
  hit.samples = m.samples;
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
