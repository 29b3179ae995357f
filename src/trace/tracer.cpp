#include "heightmarch/tracer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include "heightmarch/error.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {

namespace {

TraceRangeFn pick(const TraceRangeFn (&rows)[kFilterCount][kAddressingCount], const SamplerTexture& texture,
                  Filter filter) {
  return rows[int(filter)][int(addressing_of(texture.width, texture.height, texture.wrap))];
}

}  // namespace

Tracer::Tracer(const DepthMap& map, const TechniqueParams& params, Isa isa)
    : params_(params), isa_(isa), texture_(map, params.wrap, params.filter) {
  check_cpu_supports(isa, "tracing");
  precomputed_ = build_precomputed(map, params.wrap, info(params.technique).needs);
  // Trilinear cone stepping reads the ratios' mip chain too, as a mipmapped (depth, ratio) texture.
  if (const ConeMap* cone = precomputed_.cone_map.get(); cone && params.filter == Filter::trilinear)
    cone_ratios_ =
        SamplerTexture(DepthMap{cone->width, cone->height, cone->ratio}, params.wrap, params.filter);
  const KernelTable& table = kernel_table(isa);
  technique_kernel_ = pick(table.technique[int(params.technique)], texture_, params.filter);
  roofline_kernel_ = pick(table.sampler_roofline, texture_, params.filter);
  ceiling_kernel_ = pick(table.compute_ceiling, texture_, params.filter);
}

TraceStats Tracer::run(const RayBatch& rays, HitBuffers& hits) const {
  return run_kernel(technique_kernel_, rays, hits);
}

TraceStats Tracer::run_sampler_roofline(const RayBatch& rays, HitBuffers& hits) const {
  return run_kernel(roofline_kernel_, rays, hits);
}

TraceStats Tracer::run_compute_ceiling(const RayBatch& rays, HitBuffers& hits) const {
  return run_kernel(ceiling_kernel_, rays, hits);
}

TraceStats Tracer::run_kernel(TraceRangeFn kernel, const RayBatch& rays, HitBuffers& hits) const {
  hits.resize(rays.size());
  tbb::combinable<KernelCounters> counters;
  KernelTexture texture{texture_.texels.data(), texture_.width, texture_.height, texture_.stride,
                        texture_.wrap};
#define HEIGHTMARCH_TRACER_SLOT(id, ...) \
  if (precomputed_.id) texture.id = precomputed_.id->slot();
  HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_TRACER_SLOT)
#undef HEIGHTMARCH_TRACER_SLOT
  texture.levels = texture_.levels.data();
  texture.level_count = int(texture_.levels.size());
  if (!cone_ratios_.texels.empty()) texture.cone_map.texels = cone_ratios_.texels.data();
  const KernelParams params{
      params_.layers.min_layers, params_.layers.max_layers,
      params_.refine_steps(),    params_.scale,
      params_.discard,           {params_.light[0], params_.light[1], params_.light[2]}};
  const KernelRays kernel_rays{rays.tx.data(),    rays.ty.data(),    rays.vx.data(),
                               rays.vy.data(),    rays.vz.data(),    rays.du_dx.data(),
                               rays.dv_dx.data(), rays.du_dy.data(), rays.dv_dy.data()};
  const KernelHits out = kernel_hits(hits);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1),
                    [&](const tbb::blocked_range<std::size_t>& tiles) {
                      for (std::size_t t = tiles.begin(); t != tiles.end(); ++t)
                        kernel(texture, params, kernel_rays, out, rays.tile_offsets[t],
                               rays.tile_offsets[t + 1], counters.local());
                    });
  TraceStats stats;
  counters.combine_each([&](const KernelCounters& c) {
    stats.lane_samples += c.lane_samples;
    stats.packet_samples += c.packet_samples;
  });
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
