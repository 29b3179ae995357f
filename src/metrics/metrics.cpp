#include "heightmarch/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace heightmarch {

float uv_error_texels(float u, float v, float exact_u, float exact_v, int width, int height) {
  const double ex = (double(u) - double(exact_u)) * width;
  const double ey = (double(v) - double(exact_v)) * height;
  return float(std::sqrt(ex * ex + ey * ey));
}

std::uint64_t total_samples(const RayBatch& rays, const HitBuffers& hits) {
  std::uint64_t samples = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i)) samples += hits.samples[i];
  return samples;
}

namespace {

// Nearest-rank percentile of sorted values.
double percentile(const std::vector<float>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const std::size_t rank = std::size_t(std::ceil(p / 100.0 * double(sorted.size())));
  return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace

ErrorSummary summarize_errors(const RayBatch& rays, const HitBuffers& hits, const HitBuffers& exact,
                              int map_width, int map_height, bool shadow,
                              std::vector<float>* per_ray_error) {
  ErrorSummary s;
  s.has_shadow = shadow;
  std::vector<float> errors;
  errors.reserve(rays.ray_count);
  if (per_ray_error) per_ray_error->assign(rays.size(), 0.0f);
  double sum = 0, sum_sq = 0, depth_sum = 0, samples = 0, shadow_sum = 0;
  std::size_t wrong = 0, mismatched = 0, real = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    ++real;
    samples += hits.samples[i];
    if (hits.discarded[i]) {
      ++s.discarded;
      continue;
    }
    const float e = uv_error_texels(hits.u[i], hits.v[i], exact.u[i], exact.v[i], map_width, map_height);
    if (per_ray_error) (*per_ray_error)[i] = e;
    errors.push_back(e);
    sum += e;
    sum_sq += double(e) * e;
    wrong += e > 1.0f;
    depth_sum += std::fabs(double(hits.depth[i]) - double(exact.depth[i]));
    if (shadow) {
      shadow_sum += std::fabs(double(hits.shadow[i]) - double(exact.shadow[i]));
      mismatched += (hits.shadow[i] >= 0.5f) != (exact.shadow[i] >= 0.5f);
    }
  }
  s.rays = errors.size();
  s.samples_per_ray = real ? samples / double(real) : 0.0;
  if (errors.empty()) return s;
  const double n = double(errors.size());
  s.mean = sum / n;
  s.rms = std::sqrt(sum_sq / n);
  s.wrong_surface_rate = double(wrong) / n;
  s.depth_error_mean = depth_sum / n;
  s.shadow_error_mean = shadow_sum / n;
  s.shadow_mismatch_rate = double(mismatched) / n;
  std::sort(errors.begin(), errors.end());
  s.p50 = percentile(errors, 50);
  s.p95 = percentile(errors, 95);
  s.p99 = percentile(errors, 99);
  s.max = errors.back();
  return s;
}

std::vector<std::pair<std::string, double>> error_measures(const ErrorSummary& e) {
  const double shadow_error = e.has_shadow ? e.shadow_error_mean : std::nan("");
  const double shadow_mismatch = e.has_shadow ? e.shadow_mismatch_rate : std::nan("");
  return {{"uv_error_mean", e.mean},
          {"uv_error_rms", e.rms},
          {"uv_error_p50", e.p50},
          {"uv_error_p95", e.p95},
          {"uv_error_p99", e.p99},
          {"uv_error_max", e.max},
          {"wrong_surface_rate", e.wrong_surface_rate},
          {"depth_error_mean", e.depth_error_mean},
          {"shadow_error_mean", shadow_error},
          {"shadow_mismatch_rate", shadow_mismatch}};
}

std::vector<std::pair<std::string, double>> error_counters(const ErrorSummary& e) {
  std::vector<std::pair<std::string, double>> counters;
  for (const auto& [name, value] : error_measures(e))
    if (!std::isnan(value)) counters.emplace_back(name, value);
  return counters;
}

double layer_step_texels(const LayerSpec& layers, float scale, float vx, float vy, float vz, int map_width,
                         int map_height) {
  const double n = layer_count(layers.min_layers, layers.max_layers, vz);
  return std::hypot(scale * vx / vz / n * map_width, scale * vy / vz / n * map_height);
}

double share_within_one_layer_step(const RayBatch& rays, const HitBuffers& hits,
                                   const std::vector<float>& uv_error, const TechniqueParams& params,
                                   int map_width, int map_height) {
  std::size_t within = 0, measured = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i) || hits.discarded[i]) continue;
    within += !beyond_one_layer_step(uv_error[i], layer_step_texels(params.layers, params.scale, rays.vx[i], rays.vy[i],
                                                                    rays.vz[i], map_width, map_height));
    ++measured;
  }
  return measured ? double(within) / double(measured) : 0.0;
}

}  // namespace heightmarch
