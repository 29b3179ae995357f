#pragma once
// Relaxed cone step mapping (Policarpo and Oliveira, GPU Gems 3 ch. 18): from the top plane the
// ray steps to the boundary of the relaxed cone (heightmarch/cone_map.hpp) of the surface point
// below it, which it may cross at most once; the first read at or below the surface ends the
// stepping, then --refine halvings of the bracket between the deepest point read above the
// surface and the point read below it (or, when no read was below, the last step's end). A step
// that no longer moves the ray (in float) ends the stepping too.
//
// One read of the (depth, cone) map is one sample: the depth and the ratio of the same bilinear
// read. N (the layer spec at V.z) is the number of cone steps: at most ceil(N) reads, then the
// halvings' reads.
#include "kernels/kernel_context.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// A read this close above the surface (in depth) ends the stepping: closer the ray only crawls,
// and CPU and GLSL would part over the last float bits of a gap that no longer shows.
inline constexpr float kConeReached = 1.52587890625e-5f;  // 2^-16

template <int W, Addressing ADDRESSING>
HitPacket<W> cone(KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  KernelTexture ratios = k.texture;
  ratios.texels = k.texture.cone;
  const PacketSampler<W, ADDRESSING> cone_ratio(ratios);  // the second channel of each read

  // uv offset per unit depth, as the layered techniques' P, and r = |P|: the ray's uv per depth.
  const F p_x = ray.vx / ray.vz * F(k.params.scale);
  const F p_y = ray.vy / ray.vz * F(k.params.scale);
  const F r = sqrt(p_x * p_x + p_y * p_y);
  const I bound = to_int(ceil(k.layer_count(ray.vz)));

  I samples(0);
  F t(0.0f), above(0.0f);  // the ray's depth; the deepest depth read above the surface
  B marching = I(0) < bound;
  for (int step = 0; step < k.max_step_bound() && any(marching); ++step) {
    const F u = ray.tx - p_x * t, v = ray.ty - p_y * t;
    const F depth = k.sample(u, v, marching, samples);
    const F c = cone_ratio(u, v);
    const B stepping = marching & (depth - t > F(kConeReached));
    above = select(stepping, t, above);
    // To the cone's boundary: the ray falls (D - t) c / (r + c); straight down, to the surface.
    const F fraction = select(r + c > F(0.0f), c / (r + c), F(1.0f));
    const F next = t + (depth - t) * fraction;
    // A step too small to move t in float: as close to the surface as the ray gets.
    marching = stepping & (next > t) & (I(step + 1) < bound);
    t = select(stepping, next, t);
  }

  F lo = above, hi = t;
  for (int i = 0; i < k.params.refine_steps; ++i) {
    const F mid = (lo + hi) * F(0.5f);
    const B below = !(k.sample(ray.tx - p_x * mid, ray.ty - p_y * mid, B::all_true(), samples) > mid);
    hi = select(below, mid, hi);
    lo = select(below, lo, mid);
  }
  const F hit = (lo + hi) * F(0.5f);
  HitPacket<W> out;
  out.u = ray.tx - p_x * hit;
  out.v = ray.ty - p_y * hit;
  out.depth = hit;
  out.samples = samples;
  return out;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
