#pragma once
// Plain parallax and parallax with offset limiting: one sample at T (LearnOpenGL, the "Parallax Occlusion
// Mapping in GLSL" tutorial).
#include "kernels/kernel_context.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// uv = T - V.xy / V.z * (D(T) s); limited drops the division by V.z.
template <bool LIMITED, int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> parallax(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  HitPacket<W> hit;
  const F depth = k.sample(ray.tx, ray.ty, vbool<W>::all_true(), hit.samples);
  const F offset = depth * F(k.params.scale);
  const F dir_x = LIMITED ? ray.vx : ray.vx / ray.vz;
  const F dir_y = LIMITED ? ray.vy : ray.vy / ray.vz;
  hit.u = ray.tx - dir_x * offset;
  hit.v = ray.ty - dir_y * offset;
  hit.depth = depth;
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
