#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/exact.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {
namespace {

// Cells a path of texture offset (ox, oy) per unit depth crosses on a W x H map, at most.
double path_cells(const DepthMap& map, double ox, double oy) {
  return std::fabs(ox) * map.width + std::fabs(oy) * map.height;
}

}  // namespace

void check_exact_path_lengths(const DepthMap& map, const RayBatch& rays, const TechniqueParams& params) {
  const double s = params.scale;
  const float* L = params.light;
  if (path_cells(map, s * L[0] / L[2], s * L[1] / L[2]) > kMaxExactPathCells)
    throw InputError("the light (z = " + std::to_string(L[2]) +
                     ") grazes the surface: its path crosses more than " +
                     std::to_string(long(kMaxExactPathCells)) + " texel cells, the exact reference's limit");
  // A ray's path crosses s (|V.x| W + |V.y| H) / V.z cells (V.z > 0), compared here without the
  // division: this loop runs over every ray of every exact trace (4% of one, with it).
  const double sw = s * map.width, sh = s * map.height;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double vz = rays.vz[i];
    if (std::fabs(double(rays.vx[i])) * sw + std::fabs(double(rays.vy[i])) * sh <= kMaxExactPathCells * vz)
      continue;
    const double xy = std::hypot(double(rays.vx[i]), double(rays.vy[i]));
    const double min_vz = s * xy * (map.width + map.height) / kMaxExactPathCells;
    char text[256];
    std::snprintf(
        text, sizeof text,
        "ray %u grazes the surface: V.z = %.3g crosses more than %ld texel cells of this %dx%d depth map at "
        "scale %g, the exact reference's limit; it needs V.z >= %.3g",
        unsigned(rays.origin[i]) + 1, vz, long(kMaxExactPathCells), map.width, map.height, s, min_vz);
    throw InputError(text);
  }
}

ExactReference::ExactReference(const DepthMap& map, const TechniqueParams& params, Isa isa)
    : map_(&map), params_(params), isa_(isa), intersector_(map, params.wrap), texture_(map, params.wrap) {
  check_cpu_supports(isa, "the exact reference");  // its float pass runs at the ISA
}

void ExactReference::run(const RayBatch& rays, LightVisibility visibility, HitBuffers& hits) const {
  check_exact_path_lengths(*map_, rays, params_);
  const MinDepthPyramid& pyramid = intersector_.pyramid();
  KernelTexture texture{texture_.texels.data(), texture_.width, texture_.height, texture_.stride,
                        texture_.wrap};
  texture.min_depth_pyramid = pyramid.slot();
  const KernelParams kernel_params{
      1.0f, 1.0f, 0, params_.scale, params_.discard, {params_.light[0], params_.light[1], params_.light[2]}};
  const TraceRangeFn float_pass =
      kernel_table(isa_).exact_bound[int(addressing_of(texture.width, texture.height, texture.wrap))];
  const KernelRays kernel_rays{rays.tx.data(), rays.ty.data(), rays.vx.data(), rays.vy.data(),
                               rays.vz.data()};
  hits.resize(rays.size());
  settled_.resize(rays.size());
  clear_depth_.resize(rays.size());
  KernelHits out = kernel_hits(hits);
  out.settled = settled_.data();
  out.clear_depth = clear_depth_.data();
  const double s = params_.scale;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1),
      [&](const tbb::blocked_range<std::size_t>& tiles) {
        KernelCounters counters;
        for (std::size_t t = tiles.begin(); t != tiles.end(); ++t) {
          float_pass(texture, kernel_params, kernel_rays, out, rays.tile_offsets[t], rays.tile_offsets[t + 1],
                     counters);
          for (std::size_t i = rays.tile_offsets[t]; i < rays.tile_offsets[t + 1]; ++i) {
            if (rays.is_padding(i)) {  // a copy of a real ray: not worth a walk in double
              hits.u[i] = rays.tx[i];
              hits.v[i] = rays.ty[i];
              hits.depth[i] = 0.0f;
              hits.shadow[i] = 1.0f;
              hits.samples[i] = 0;
              hits.discarded[i] = 0;
              continue;
            }
            // Most rays the float pass finished in double in the cell it stopped in or the next; the
            // others (and every ray whose light is walked, from the hit in double) go on in the double
            // walk from where it stopped: the path is clear before it.
            const bool final = settled_[i] != 0;
            if (final && visibility == LightVisibility::skip) {  // the float pass wrote the rest
              hits.samples[i] += 1;
              continue;
            }
            // A final ray's depth is its hit rounded to float: the path is clear just above it.
            const double vz = rays.vz[i], offset_per_depth = s / vz;
            const double from =
                final ? std::max(0.0, double(hits.depth[i]) - 0x1p-20) : double(clear_depth_[i]);
            const PathHit hit =
                intersector_.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], vz, s, from);
            const double d = hit.t;
            const double u = rays.tx[i] - d * offset_per_depth * rays.vx[i];
            const double v = rays.ty[i] - d * offset_per_depth * rays.vy[i];
            hits.u[i] = float(u);
            hits.v[i] = float(v);
            hits.depth[i] = float(d);
            hits.samples[i] += hit.cells;
            hits.shadow[i] =
                visibility == LightVisibility::compute && !intersector_.visible(u, v, d, params_.light, s)
                    ? 0.0f
                    : 1.0f;
            hits.discarded[i] = params_.discard && (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0);
          }
        }
      });
}

HitBuffers exact_hits(const DepthMap& map, const RayBatch& rays, const TechniqueParams& params,
                      LightVisibility visibility, Isa isa) {
  HitBuffers hits;
  ExactReference(map, params, isa).run(rays, visibility, hits);
  return hits;
}

}  // namespace heightmarch
