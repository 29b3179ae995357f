#pragma once
// The layer march of steep parallax (LearnOpenGL's loop): layers of depth 1/N along the ray until
// the first layer below the surface. Steep, relief, POM, secant and the shadow start from its state.
#include "kernels/kernel_context.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W>
struct LayerMarch {
  vfloat<W> u, v;              // current texture coordinates
  vfloat<W> delta_u, delta_v;  // texture step per layer
  vfloat<W> layer_depth;       // 1 / N
  vfloat<W> current_layer_depth;
  vfloat<W> depth_map_value;  // D at (u, v)
  vint<W> samples;
};

// LIMITED: the step is s V.xy / N (the "Steep Parallax Mapping" tutorial), else s V.xy / V.z / N.
template <bool LIMITED, int W, Addressing ADDRESSING, Taps TAPS, Filter FILTER>
LayerMarch<W> march_layers(KernelContext<W, ADDRESSING, TAPS, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  LayerMarch<W> m;
  const F num_layers = k.layer_count(ray.vz);
  m.layer_depth = F(1.0f) / num_layers;
  m.current_layer_depth = F(0.0f);
  const F p_x = (LIMITED ? ray.vx : ray.vx / ray.vz) * F(k.params.scale);
  const F p_y = (LIMITED ? ray.vy : ray.vy / ray.vz) * F(k.params.scale);
  m.delta_u = p_x / num_layers;
  m.delta_v = p_y / num_layers;
  m.u = ray.tx;
  m.v = ray.ty;
  m.samples = I(0);
  m.depth_map_value = k.sample(m.u, m.v, B::all_true(), m.samples);

  // The march itself advances every lane unconditionally, so the sample positions (and the
  // gathers) never wait for the previous comparison; lanes still above the surface record it.
  // It works on locals: m is the caller's memory, and writing it every step costs stores.
  const I bound = k.step_bound(num_layers);
  const F delta_u = m.delta_u, delta_v = m.delta_v, layer_depth = m.layer_depth;
  F u = m.u, v = m.v, current_layer_depth = m.current_layer_depth;
  F last_u = u, last_v = v, last_value = m.depth_map_value, last_layer_depth = current_layer_depth;
  I samples = m.samples;
  B active = current_layer_depth < last_value;
  int step = 1;
  const auto layer_step = [&](bool bounded) {
    u = u - delta_u;
    v = v - delta_v;
    const F depth_map_value = k.read(u, v);
    k.count_lanes(active, samples, 1);
    current_layer_depth = current_layer_depth + layer_depth;
    last_u = select(active, u, last_u);
    last_v = select(active, v, last_v);
    last_value = select(active, depth_map_value, last_value);
    last_layer_depth = select(active, current_layer_depth, last_layer_depth);
    active = active & (current_layer_depth < depth_map_value);
    if (bounded) active = active & (I(step) < bound);
  };
  // Up to the packet's smallest bound every lane passes its bound test (step < bound): those
  // steps skip it.
  const int unbounded_steps = reduce_min(bound) - 1;
  for (; step <= unbounded_steps && any(active); ++step) layer_step(false);
  for (; step <= k.max_step_bound() && any(active); ++step) layer_step(true);
  k.count_packet_reads(step - 1);
  m.u = last_u;
  m.v = last_v;
  m.depth_map_value = last_value;
  m.current_layer_depth = last_layer_depth;
  m.samples = samples;
  return m;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
