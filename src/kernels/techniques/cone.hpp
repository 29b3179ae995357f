#pragma once
// Relaxed cone step mapping (Policarpo and Oliveira, GPU Gems 3 ch. 18): from the top plane the
// ray steps to the boundary of the relaxed cone (heightmarch/cone_map.hpp) of the surface point
// below it, which it may cross at most once. The stepping ends at the first read below the
// surface, then at most --refine halvings of the bracket between the deepest point read above
// the surface and that one, while it is wider than kConeReached; or after ceil(N) steps (N: the
// layer spec at V.z), then the same halvings up to the last step's end, which was not read. It
// also ends, without halvings, when a read finds the ray on the surface or within kConeReached
// above it, or a step no longer moves it (in float).
//
// One read of the (depth, cone) map is one sample: the depth and the ratio of the same bilinear
// read. At most ceil(N) + refine samples.
#include "kernels/kernel_context.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// A read this close above the surface (in depth) ends the stepping: closer the ray only crawls,
// and CPU and GLSL would part over the last float bits of a gap that no longer shows.
inline constexpr float kConeReached = 1.52587890625e-5f;  // 2^-16

template <int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> cone(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;

  // uv offset per unit depth, as the layered techniques' P, and r = |P|: the ray's uv per depth.
  const F p_x = ray.vx / ray.vz * F(k.params.scale);
  const F p_y = ray.vy / ray.vz * F(k.params.scale);
  const F r = sqrt(p_x * p_x + p_y * p_y);
  const I bound = to_int(ceil(k.layer_count(ray.vz)));

  I samples(0);
  F t(0.0f), above(0.0f);  // the ray's depth; the deepest depth read above the surface
  B marching = I(0) < bound;
  B bracketed = !B::all_true();  // the surface may lie between `above` and t
  for (int step = 0; step < k.max_step_bound() && any(marching); ++step) {
    const F u = ray.tx - p_x * t, v = ray.ty - p_y * t;
    const F depth = k.sample(u, v, marching, samples);
    const F c = k.read(k.texture.cone_map.texels, u, v);  // the second channel of the read
    const B stepping = marching & (depth - t > F(kConeReached));
    const B crossed = marching & (depth < t);
    above = select(stepping, t, above);
    // To the cone's boundary: the ray falls (D - t) c / (r + c); straight down, to the surface.
    const F fraction = select(r + c > F(0.0f), c / (r + c), F(1.0f));
    const F next = t + (depth - t) * fraction;
    // A step too small to move t in float: as close to the surface as the ray gets.
    const B moving = stepping & (next > t);
    const B last = !(I(step + 1) < bound);
    bracketed = bracketed | crossed | (moving & last);  // the last step's end is not read
    marching = moving & !last;
    t = select(stepping, next, t);
  }

  // Halvings where a crossing may lie behind t, while the bracket is wider than kConeReached; a
  // ray that came within kConeReached above the surface, or stopped moving, ends at t.
  F lo = above, hi = t;
  B halving = bracketed & (hi - lo > F(kConeReached));
  for (int i = 0; i < k.params.refine_steps && any(halving); ++i) {
    const F mid = (lo + hi) * F(0.5f);
    const B below = !(k.sample(ray.tx - p_x * mid, ray.ty - p_y * mid, halving, samples) > mid);
    hi = select(halving & below, mid, hi);
    lo = select(halving & !below, mid, lo);
    halving = halving & (hi - lo > F(kConeReached));
  }
  const F hit = select(bracketed, (lo + hi) * F(0.5f), t);
  HitPacket<W> out;
  out.u = ray.tx - p_x * hit;
  out.v = ray.ty - p_y * hit;
  out.depth = hit;
  out.samples = samples;
  return out;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
