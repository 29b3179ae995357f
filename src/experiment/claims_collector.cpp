// The claims' figures: each claims row's summary from its Measurement, and its per-ray figures
// (relative error, error and tunnelling where the depth map changes sharply or has thin features)
// from the hits, the exact hits and the depth map while the row is traced.
#include "experiment/claims_collector.hpp"

#include <algorithm>
#include <cmath>

#include "heightmarch/sampler.hpp"

namespace heightmarch {
namespace {

constexpr double kThinDepth = 1.0 / 8.0;  // thinner than one layer at 8 layers
constexpr int kMaxThicknessSteps = 4096;

bool is_claims_trace(const Configuration& c) {
  return (c.purposes & kPurposeClaims) && c.kind == RunKind::trace;
}
bool is_large_map_trace(const Configuration& c) {
  return (c.purposes & kPurposeLargeMaps) && c.kind == RunKind::trace;
}

// |grad D| at (u, v) in depth per texel, by central differences one texel apart: a step between
// two texels reads as 0.5 per texel, a smooth slope as its slope.
double depth_gradient(const DepthMap& map, Wrap wrap, float u, float v) {
  const float du = 1.0f / float(map.width), dv = 1.0f / float(map.height);
  const double gx = 0.5 * (double(sample_depth(map, wrap, u + du, v)) - sample_depth(map, wrap, u - du, v));
  const double gy = 0.5 * (double(sample_depth(map, wrap, u, v + dv)) - sample_depth(map, wrap, u, v - dv));
  return std::hypot(gx, gy);
}

// Whether the ray leaves the solid again within kThinDepth of the depth range after its exact hit:
// it passes through a feature thinner than one layer at 8 layers. Marched in steps of at most half
// a texel along the ray and 1/512 of the depth range.
bool hits_thin_feature(const DepthMap& map, const TechniqueParams& p, float tx, float ty, float vx, float vy,
                       float vz, float hit_depth) {
  const double du = p.scale * vx / vz, dv = p.scale * vy / vz;  // uv per unit depth
  const double texels_per_depth = std::hypot(du * map.width, dv * map.height);
  const double step = std::min(1.0 / 512.0, texels_per_depth > 0 ? 0.5 / texels_per_depth : 1.0);
  const double end = std::min(1.0, double(hit_depth) + kThinDepth);
  for (int k = 1; k <= kMaxThicknessSteps; ++k) {
    const double d = hit_depth + k * step;
    if (d >= end) return false;
    if (sample_depth(map, p.wrap, float(tx - d * du), float(ty - d * dv)) > d) return true;
  }
  return false;
}

}  // namespace

void ClaimsCollector::observe(const TracedRow& traced) {
  const Measurement& row = traced.row;
  const Configuration& c = row.config;
  if (!is_claims_trace(c) || !row.errors) return;
  const RayBatch& rays = traced.rays;
  const HitBuffers &hits = traced.hits, &exact = traced.exact;
  const DepthMap& map = traced.map;
  const std::size_t n = rays.size();
  // The features of a scene (one heightfield, view, scale and wrap) are the same for all of its
  // rows, which the plan measures one after another: computed once per scene.
  const bool same_scene = features_.heightfield == c.heightfield && features_.view == c.view &&
                          features_.scale == c.params.scale && features_.wrap == c.params.wrap &&
                          features_.sharp.size() == n;
  if (!same_scene) {
    features_ = SceneFeatures{c.heightfield, c.view, c.params.scale, c.params.wrap, {}, {}, {}, false};
    std::vector<double> gradient(n, 0.0);
    std::vector<std::size_t> order;
    features_.thin.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (rays.is_padding(i)) continue;
      gradient[i] = depth_gradient(map, c.params.wrap, exact.u[i], exact.v[i]);
      features_.thin[i] = hits_thin_feature(map, c.params, rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i],
                                            rays.vz[i], exact.depth[i]);
      order.push_back(i);
    }
    // By rank (ties by ray order, so the split is deterministic): top decile sharp, bottom half smooth.
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return gradient[a] < gradient[b]; });
    features_.sharp.assign(n, 0);
    features_.smooth.assign(n, 0);
    const std::size_t half = order.size() / 2, decile = order.size() - order.size() / 10;
    for (std::size_t r = 0; r < order.size(); ++r) {
      if (r < half) features_.smooth[order[r]] = 1;
      if (r >= decile) features_.sharp[order[r]] = 1;
    }
    features_.has_spread = !order.empty() && decile < order.size() && half > 0 &&
                           gradient[order[decile]] > gradient[order[half - 1]];
  }
  const bool layered = info(c.params.technique).layered;
  const LayerSpec& layers = c.params.layers;
  struct Subset {
    std::size_t rays = 0, beyond = 0;
    double error = 0;
    void add(double e, bool b) { ++rays, error += e, beyond += b; }
    double error_mean() const { return rays ? error / double(rays) : 0.0; }
    double beyond_share() const {
      return rays >= std::size_t(kMinFeatureRays) ? double(beyond) / double(rays) : -1.0;
    }
  } all, sharp, smooth, thin;
  double offset = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rays.is_padding(i) || hits.discarded[i]) continue;
    offset += std::hypot((double(rays.tx[i]) - exact.u[i]) * map.width,
                         (double(rays.ty[i]) - exact.v[i]) * map.height);
    const double e = traced.search_error[i];
    bool beyond = false;
    if (layered)
      beyond = beyond_one_layer_step(e, layer_step_texels(layers, c.params.scale, rays.vx[i], rays.vy[i],
                                                          rays.vz[i], map.width, map.height));
    all.add(e, beyond);
    if (features_.sharp[i]) sharp.add(e, beyond);
    if (features_.smooth[i]) smooth.add(e, beyond);
    if (features_.thin[i]) thin.add(e, beyond);
  }
  ClaimFigure::PerRay& f = per_row_[row.id];
  f.offset_mean = all.rays ? offset / double(all.rays) : 0.0;
  f.sharp_error_mean = features_.has_spread && sharp.rays && smooth.rays ? sharp.error_mean() : -1.0;
  f.smooth_error_mean = features_.has_spread && sharp.rays && smooth.rays ? smooth.error_mean() : -1.0;
  f.thin_share = all.rays ? double(thin.rays) / double(all.rays) : 0.0;
  if (layered) {
    f.beyond_one_layer = all.rays ? double(all.beyond) / double(all.rays) : 0.0;
    f.sharp_beyond_one_layer = features_.has_spread ? sharp.beyond_share() : -1.0;
    f.thin_beyond_one_layer = thin.beyond_share();
  }
}

ClaimsData ClaimsCollector::data(const std::vector<Measurement>& rows) const {
  ClaimsData data;
  for (const Measurement& m : rows) {
    const Configuration& c = m.config;
    if (!(is_claims_trace(c) || is_large_map_trace(c)) || !m.errors) continue;
    ClaimFigure f;
    f.heightfield = c.heightfield.label();
    f.row = {c.params.technique, c.params.layers, ClaimView::default_view, 0.0};
    if (c.view.kind == ViewSpec::Kind::sweep)
      f.row = {c.params.technique, c.params.layers, ClaimView::sweep, c.view.theta_degrees};
    // The search error, in texels: what the tutorials' claims are about (the layers, the
    // refinement), the same measure under both filters (under bilinear the uv error itself).
    f.uv_error_mean = m.errors->search.mean;
    f.uv_error_p95 = m.errors->search.p95;
    f.uv_error_p99 = m.errors->search.p99;
    f.wrong_surface_rate = m.errors->search.wrong_rate;
    f.samples_per_ray = m.rays ? double(m.samples) / double(m.rays) : 0.0;
    f.within_one_layer = m.errors->within_one_layer_step.value_or(0.0);
    const Spread speed = spread_of(m.rays_per_second());
    f.rays_per_second = speed.median;
    f.rays_per_second_min = speed.min;
    f.rays_per_second_max = speed.max;
    if (const auto it = per_row_.find(m.id); it != per_row_.end()) f.per_ray = it->second;
    if (is_claims_trace(c)) data.figures.push_back(f);
    if (is_large_map_trace(c)) {
      f.row.view = ClaimView::large_map;
      data.figures.push_back(f);
    }
  }
  return data;
}

}  // namespace heightmarch
