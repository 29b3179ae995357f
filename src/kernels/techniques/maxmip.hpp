#pragma once
// Maximum-mipmap tracing: the pyramid walk (kernels/pyramid_walk.hpp), then the first root of the
// bilinear patch in the cell it stopped in. Exact up to float rounding, at a cost that grows with
// the depth features on the ray, not with the resolution.
#include "kernels/pyramid_walk.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Addressing ADDRESSING>
HitPacket<W> maxmip(KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  const TexelPath<W> path = texel_path(k, ray);
  const F &p_x = path.p_x, &p_y = path.p_y, &x0 = path.x0, &y0 = path.y0, &dx = path.dx, &dy = path.dy;
  const PyramidWalk<W> walk = walk_pyramid<false>(k, x0, y0, dx, dy, F(0.0f));
  // Reached: the patch's first crossing; cut off by the bound: the deepest point known clear;
  // else no hit before depth 1.
  const F hit_t = select(walk.reached, walk.t + first_root(walk.c0, walk.c1, walk.c2, walk.span),
                         select(walk.cut_off, walk.t, F(1.0f)));
  HitPacket<W> out;
  out.u = ray.tx - p_x * hit_t;
  out.v = ray.ty - p_y * hit_t;
  out.depth = hit_t;
  out.samples = walk.samples;
  return out;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
