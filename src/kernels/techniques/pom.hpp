#pragma once
// Parallax occlusion mapping: steep parallax, then the tutorial's linear interpolation between
// the last two layers, re-reading the previous layer's depth as LearnOpenGL does.
#include "kernels/layer_march.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// Also the compute ceiling's kernel, on register taps (Taps::registers).
template <int W, Addressing ADDRESSING, Taps TAPS, Filter FILTER>
HitPacket<W> pom(KernelContext<W, ADDRESSING, TAPS, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  LayerMarch<W> m = march_layers<false>(k, ray);
  const F prev_u = m.u + m.delta_u;
  const F prev_v = m.v + m.delta_v;
  const F after_depth = m.depth_map_value - m.current_layer_depth;
  const F before_depth =
      k.sample(prev_u, prev_v, vbool<W>::all_true(), m.samples) - m.current_layer_depth + m.layer_depth;
  // The tutorial divides 0 by 0 when both differences vanish; such a lane keeps its layer.
  const F denominator = after_depth - before_depth;
  const F weight = select(denominator != F(0.0f), after_depth / denominator, F(0.0f));
  const F one_minus_weight = F(1.0f) - weight;
  HitPacket<W> hit;
  hit.u = prev_u * weight + m.u * one_minus_weight;
  hit.v = prev_v * weight + m.v * one_minus_weight;
  hit.depth = (m.current_layer_depth - m.layer_depth) * weight + m.current_layer_depth * one_minus_weight;
  hit.samples = m.samples;
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
