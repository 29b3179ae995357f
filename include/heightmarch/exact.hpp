#pragma once
// The exact ray/heightfield intersection (docs/conventions.md), in double precision.
#include <cstdint>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/min_depth_pyramid.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

// A path through the heightfield, linear in t: texel-space position (x, y) = origin + t dir,
// with x = u W - 0.5 as in the sampler, and depth = depth0 + t ddepth.
struct HeightfieldPath {
  double x0, y0, dx, dy;
  double depth0, ddepth;
  double t_max;
};

struct PathHit {
  bool found = false;
  double t = 0.0;
  std::uint32_t cells = 0;  // texel cells solved on the way
};

// Walks the texel cells the path crosses (2D DDA), skipping blocks whose minimum depth lies
// below the path with a min-depth mip pyramid, and solves each cell's quadratic in double.
class ExactIntersector {
 public:
  ExactIntersector(const DepthMap& map, Wrap wrap);

  // Smallest t in [from, t_max] with depth(t) >= D(x(t), y(t)). From 0 the walk starts high in
  // the pyramid; from a later t (where a float pass stopped, the path clear before it) it starts
  // in that cell.
  PathHit first_hit(const HeightfieldPath& path, double from = 0.0) const;

  // d* of docs/conventions.md for one ray, and the cells solved; `from` as for first_hit.
  PathHit intersect(double tx, double ty, double vx, double vy, double vz, double scale,
                    double from = 0.0) const;

  // Whether the light is visible from the surface point at uv (depth d) along unit L.
  bool visible(double u, double v, double depth, const float light[3], double scale) const;

  // Bilinear depth at texel-space (x, y), in double (the sampling formula (docs/conventions.md)).
  double depth_at(double x, double y) const;

  const MinDepthPyramid& pyramid() const { return pyramid_; }

 private:
  double texel(long long i, long long j) const;
  bool cell_first_root(long long ci, long long cj, const HeightfieldPath& path, double t0, double t1,
                       double& t_hit) const;

  const DepthMap* map_;
  Wrap wrap_;
  MinDepthPyramid pyramid_;
};

// The longest path, in texel cells, the exact reference walks for one ray or its light path:
// past it a grazing ray's walk can take seconds (a ray at V.z = 6e-7 and scale 1 crosses 8.5e8
// cells of a 512 x 512 map), and float texture coordinates that far out have lost the precision
// any technique would need. At the default scale 0.1 on 512 x 512 this admits angles up to
// 89.997 degrees.
inline constexpr double kMaxExactPathCells = double(1 << 20);

// Throws InputError naming the first ray (or the light) whose path through the depth map,
// scale s |V.xy| / V.z (W + H) cells, is longer than kMaxExactPathCells.
void check_exact_path_lengths(const DepthMap& map, const RayBatch& rays, const TechniqueParams& params);

// The exact answer for every ray of a batch. Each tile goes through a conservative float pass of
// the pyramid walk at one ISA (maxmip's walk with every test loosened by a bound on its rounding:
// src/exact/exact_bound.hpp), which stops each ray in the first cell the exact path may touch and
// solves that cell (and, where the path is clear through it, the next) in double; the double
// walk goes on from there for the rays it does not settle. The answer does not depend on the ISA (every ISA's
// pass is bit-identical to the scalar one).
enum class LightVisibility { skip, compute };
inline LightVisibility visibility_for(Technique technique) {
  return writes_visibility(info(technique)) ? LightVisibility::compute : LightVisibility::skip;
}

// Built once per depth map (which it keeps a pointer to) and parameters (the pyramid, the float
// pass's texture), like a Tracer, so that repeated runs time only the tracing. Uses params'
// scale, wrap, light and discard; not its technique.
class ExactReference {
 public:
  ExactReference(const DepthMap& map, const TechniqueParams& params, Isa isa = best_isa());

  // In parallel over the batch's tiles under the current thread limit: uv and d* per ray, the
  // texel cells tested (by the float pass, then solved in double) in `samples`, the discard flag
  // as a technique would set it, and in `shadow` the light's exact visibility (0 or 1) from the
  // exact hit when `visibility` asks for it (a second walk per ray, only the shadow technique
  // needs), else 1. Checks path lengths first.
  // Not to be called on one reference from two threads at once: its float pass's own outputs
  // are kept between runs, so that timed runs allocate nothing.
  void run(const RayBatch& rays, LightVisibility visibility, HitBuffers& hits) const;

 private:
  const DepthMap* map_;
  TechniqueParams params_;
  Isa isa_;
  ExactIntersector intersector_;
  SamplerTexture texture_;
  // The float pass's outputs (the hit list's exact_pass rows, hits.hpp): whether it settled a ray
  // (its hit, in the hits, is final) and how far the ray's path is certainly clear.
  mutable std::vector<std::uint8_t> settled_;
  mutable std::vector<float> clear_depth_;
};

HitBuffers exact_hits(const DepthMap& map, const RayBatch& rays, const TechniqueParams& params,
                      LightVisibility visibility, Isa isa = best_isa());

}  // namespace heightmarch
