#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "heightmarch/metrics.hpp"
#include "heightmarch/trace.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {
namespace {

TraceRangeFn kernels_for(Isa isa) {
  switch (isa) {
    case Isa::scalar: return isa_scalar::trace_range;
    case Isa::sse42: return isa_sse42::trace_range;
    case Isa::avx2: return isa_avx2::trace_range;
    case Isa::avx512: return isa_avx512::trace_range;
  }
  return isa_scalar::trace_range;
}

// The exact technique: uv, depth and cells solved per ray, and the light's exact visibility.
void trace_exact(const ExactIntersector& exact, const TechniqueParams& params, const RayBatch& rays,
                 HitBuffers& hits, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
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
}

}  // namespace

Tracer::Tracer(const DepthMap& map, const TechniqueParams& params, Isa isa)
    : map_(&map), params_(params), isa_(isa) {
  if (params.technique == Technique::exact)
    exact_ = std::make_unique<ExactIntersector>(map, params.wrap);
  else
    texture_ = SamplerTexture(map, params.wrap);
}

TraceStats Tracer::run(const RayBatch& rays, HitBuffers& hits) const { return run_kernels(rays, hits, false); }

TraceStats Tracer::run_sampler_roofline(const RayBatch& rays, HitBuffers& hits) const {
  return run_kernels(rays, hits, true);
}

TraceStats Tracer::run_kernels(const RayBatch& rays, HitBuffers& hits, bool roofline) const {
  hits.resize(rays.size());
  tbb::combinable<KernelCounters> counters;
  const KernelTexture texture{texture_.texels.data(), texture_.width, texture_.height,
                              texture_.stride, texture_.wrap};
  const KernelParams params{params_.technique, params_.layers.min_layers, params_.layers.max_layers,
                            params_.refine_steps, params_.scale, params_.discard,
                            {params_.light[0], params_.light[1], params_.light[2]}, roofline};
  const KernelRays kernel_rays{rays.tx.data(), rays.ty.data(), rays.vx.data(), rays.vy.data(),
                               rays.vz.data()};
  const KernelHits kernel_hits{hits.u.data(), hits.v.data(), hits.depth.data(), hits.shadow.data(),
                               hits.samples.data(), hits.discarded.data()};
  const TraceRangeFn kernels = kernels_for(isa_);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1),
                    [&](const tbb::blocked_range<std::size_t>& tiles) {
                      for (std::size_t t = tiles.begin(); t != tiles.end(); ++t) {
                        const std::size_t begin = rays.tile_offsets[t], end = rays.tile_offsets[t + 1];
                        if (exact_)
                          trace_exact(*exact_, params_, rays, hits, begin, end);
                        else
                          kernels(texture, params, kernel_rays, kernel_hits, begin, end, counters.local());
                      }
                    });
  TraceStats stats;
  counters.combine_each([&](const KernelCounters& c) {
    stats.lane_samples += c.lane_samples;
    stats.packet_samples += c.packet_samples;
  });
  stats.samples = total_samples(rays, hits);
  if (exact_) stats.lane_samples = stats.packet_samples = stats.samples;
  return stats;
}

struct ThreadLimitState {
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads)
    : threads_(threads > 0 ? threads : tbb::info::default_concurrency()),
      state_(new ThreadLimitState{
          tbb::global_control(tbb::global_control::max_allowed_parallelism, std::size_t(threads_))}) {}

ThreadLimit::~ThreadLimit() = default;

}  // namespace heightmarch
