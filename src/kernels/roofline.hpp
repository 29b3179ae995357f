#pragma once
// The sampler alone, at the positions a layered march visits (T - k delta, k = 0..N), with every
// lane active and no control flow: the practical ceiling of samples/s for a packet kernel.
#include "kernels/kernel_context.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> sampler_roofline(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k,
                              const RayPacket<W>& ray) {
  using F = vfloat<W>;
  HitPacket<W> hit;
  const F num_layers(k.params.max_layers);
  const F delta_u = ray.vx / ray.vz * F(k.params.scale) / num_layers;
  const F delta_v = ray.vy / ray.vz * F(k.params.scale) / num_layers;
  F u = ray.tx, v = ray.ty, sum(0.0f);
  const int steps = int(k.params.max_layers) + 1;
  for (int step = 0; step < steps; ++step) {
    sum = sum + k.sample(u, v, vbool<W>::all_true(), hit.samples);
    u = u - delta_u;
    v = v - delta_v;
  }
  hit.u = u;
  hit.v = v;
  hit.depth = sum;  // keeps the samples alive
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
