#pragma once
// The exact ray/heightfield intersection (docs/conventions.md), in double precision.
#include <cstdint>
#include <memory>
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
  struct Cells;  // the walk's view of the surface (src/exact/cell_walk.hpp)
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

// The exact hit on the surface a ray reads (docs/conventions.md#filters): under trilinear
// filtering, the blend a + f (b - a) of the two mip levels of its level of detail
// (level_of_detail(), from its footprint, as the kernels take it), and level 0's bilinear surface
// where that is what it reads (a level of detail of 0, bilinear filtering, a technique that reads
// texels: TechniqueParams::filter_read()). Two bilinear levels blend into a surface that is
// bilinear on each piece of the union of their cell grids, so each piece is solved exactly as the
// exact reference solves a cell, and the walk skips blocks with the blend of the two levels'
// min-depth pyramids over level a's cells. Built once per depth map and parameters (its mip
// chain, one intersector per level, a pyramid per pair of levels); uses params' scale, wrap,
// filter and discard, and which surface its technique reads.
class FilteredExactReference {
 public:
  FilteredExactReference(const DepthMap& map, const TechniqueParams& params);
  ~FilteredExactReference();

  // Per ray in parallel over tiles: uv and depth on the surface it reads, the cells solved in
  // `samples`, the discard flag as a technique would set it, and the light's visibility from
  // `level0`. A ray that reads level 0 takes `level0`'s hit as it is (the exact reference's for the
  // same rays and parameters: bit for bit today's reference there). Checks path lengths first.
  void run(const RayBatch& rays, const HitBuffers& level0, HitBuffers& hits) const;

  // d* of one ray on the trilinear surface at level of detail `lod` (level_of_detail()'s, in [0,
  // the last level]), from depth 0, and the cells solved.
  PathHit intersect(double tx, double ty, double vx, double vy, double vz, float lod) const;

 private:
  struct Levels;
  const DepthMap* map_;
  TechniqueParams params_;
  std::unique_ptr<Levels> levels_;
};

}  // namespace heightmarch
