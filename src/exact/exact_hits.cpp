#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "heightmarch/exact.hpp"

namespace heightmarch {

HitBuffers exact_hits(const DepthMap& map, const RayBatch& rays, const TechniqueParams& params) {
  const ExactIntersector exact(map, params.wrap);
  HitBuffers hits;
  hits.resize(rays.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1),
                    [&](const tbb::blocked_range<std::size_t>& tiles) {
    for (std::size_t t = tiles.begin(); t != tiles.end(); ++t)
      for (std::size_t i = rays.tile_offsets[t]; i < rays.tile_offsets[t + 1]; ++i) {
        const double vz = rays.vz[i];
        const PathHit hit = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], vz, params.scale);
        const double d = hit.t;
        const double u = rays.tx[i] - d * params.scale * rays.vx[i] / vz;
        const double v = rays.ty[i] - d * params.scale * rays.vy[i] / vz;
        hits.u[i] = float(u);
        hits.v[i] = float(v);
        hits.depth[i] = float(d);
        hits.samples[i] = hit.cells;
        hits.shadow[i] = exact.visible(u, v, d, params.light, params.scale) ? 1.0f : 0.0f;
        hits.discarded[i] = params.discard && (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0);
      }
  });
  return hits;
}

}  // namespace heightmarch
