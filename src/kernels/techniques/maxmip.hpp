#pragma once
// Maximum-mipmap tracing: the pyramid walk (kernels/pyramid_walk.hpp), then the first root of the
// bilinear patch in the cell it stopped in. Exact up to float rounding, at a cost that grows with
// the depth features on the ray, not with the resolution.
#include "kernels/pyramid_walk.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The walk of each ray of the packet, queued.
template <int W, Addressing ADDRESSING>
void queue_maxmip(const KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray, WalkQueue& queue, int i) {
  const TexelPath<W> path = texel_path(k, ray);
  queue_walk(k, path.x0, path.y0, path.dx, path.dy, vfloat<W>(0.0f), queue, i);
}

// The packet's hits from its walks.
template <int W, Addressing ADDRESSING>
HitPacket<W> maxmip(KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray, const PyramidWalk<W>& walk) {
  using F = vfloat<W>;
  const TexelPath<W> path = texel_path(k, ray);
  // Reached: the patch's first crossing; cut off by the bound: the deepest point known clear;
  // else no hit before depth 1.
  const F hit_t = select(walk.reached, walk.t + first_root(walk.c0, walk.c1, walk.c2, walk.span),
                         select(walk.cut_off, walk.t, F(1.0f)));
  HitPacket<W> out;
  out.u = ray.tx - path.p_x * hit_t;
  out.v = ray.ty - path.p_y * hit_t;
  out.depth = hit_t;
  out.samples = walk.samples;
  return out;
}

// Its walk's first step: maxmip walks the pyramid as it is (a crossing may end the walk).
template <>
struct WalkSteps<Technique::maxmip> {
  static constexpr bool kConservative = false;
  template <class Context, class Ray>
  void queue(const Context& k, const Ray& ray, WalkQueue& queue, int i) const {
    queue_maxmip(k, ray, queue, i);
  }
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
