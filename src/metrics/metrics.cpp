#include "heightmarch/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

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

namespace {

// Whether the hits carry this output as a technique writing `written` does, measured against the
// light's visibility.
bool measured_against_visibility(const HitChannelInfo& c, Writes written) {
  return c.against == MeasuredAgainst::visibility && c.writer == ChannelWriter::optional &&
         (unsigned(written) >> unsigned(c.id)) & 1u;
}

// The array of an output measured against the visibility (a float one: a factor).
const std::vector<float>& float_channel(const HitBuffers& hits, HitChannel channel) {
  const std::vector<float>* found = nullptr;
  hits.for_each([&](HitChannel c, const auto& values) {
    if constexpr (std::is_same_v<std::decay_t<decltype(values)>, std::vector<float>>)
      if (c == channel) found = &values;
  });
  return *found;
}

}  // namespace

ErrorSummary summarize_errors(const RayBatch& rays, const HitBuffers& hits, const HitBuffers& exact,
                              int map_width, int map_height, Writes written,
                              std::vector<float>* per_ray_error) {
  ErrorSummary s;
  std::vector<float> errors;
  errors.reserve(rays.ray_count);
  if (per_ray_error) per_ray_error->assign(rays.size(), 0.0f);
  double sum = 0, sum_sq = 0, depth_sum = 0, samples = 0;
  std::size_t wrong = 0, real = 0;
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
  }
  s.rays = errors.size();
  s.samples_per_ray = real ? samples / double(real) : 0.0;
  if (errors.empty()) return s;
  const double n = double(errors.size());
  s.mean = sum / n;
  s.rms = std::sqrt(sum_sq / n);
  s.wrong_surface_rate = double(wrong) / n;
  s.depth_error_mean = depth_sum / n;
  // Each output against the exact visibility (the exact hits' shadow: 0 or 1), on the same rays.
  for (const HitChannelInfo& c : hit_channels()) {
    if (!measured_against_visibility(c, written)) continue;
    const std::vector<float>& value = float_channel(hits, c.id);
    double error_sum = 0;
    std::size_t mismatched = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (rays.is_padding(i) || hits.discarded[i]) continue;
      error_sum += std::fabs(double(value[i]) - double(exact.shadow[i]));
      mismatched += (value[i] >= 0.5f) != (exact.shadow[i] >= 0.5f);
    }
    s.visibility[std::size_t(c.id)] = {true, error_sum / n, double(mismatched) / n};
  }
  std::sort(errors.begin(), errors.end());
  s.p50 = percentile(errors, 50);
  s.p95 = percentile(errors, 95);
  s.p99 = percentile(errors, 99);
  s.max = errors.back();
  return s;
}

const std::vector<ErrorMeasure>& error_measure_list() {
  static const std::vector<ErrorMeasure> list = [] {
    std::vector<ErrorMeasure> measures = {
#define HEIGHTMARCH_HIT_MEASURE_NAME(name, member, label) {#name, label},
        HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_HIT_MEASURE_NAME)
#undef HEIGHTMARCH_HIT_MEASURE_NAME
    };
    for (const HitChannelInfo& c : hit_channels())
      if (c.against == MeasuredAgainst::visibility) {
        const std::string name(c.name), label(c.label);
        measures.push_back({name + "_error_mean", "mean " + label + " error"});
        measures.push_back({name + "_mismatch_rate", name + " mismatch (share)"});
      }
    return measures;
  }();
  return list;
}

std::string error_measure_names() {
  std::string names;
  for (const ErrorMeasure& m : error_measure_list()) names += (names.empty() ? "" : ",") + m.name;
  return names;
}

std::vector<std::pair<std::string, double>> error_measures(const ErrorSummary& e) {
  std::vector<std::pair<std::string, double>> measures = {
#define HEIGHTMARCH_HIT_MEASURE_VALUE(name, member, label) {#name, e.member},
      HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_HIT_MEASURE_VALUE)
#undef HEIGHTMARCH_HIT_MEASURE_VALUE
  };
  for (const HitChannelInfo& c : hit_channels())
    if (c.against == MeasuredAgainst::visibility) {
      const ErrorSummary::VisibilityError& v = e.visibility[std::size_t(c.id)];
      measures.emplace_back(std::string(c.name) + "_error_mean", v.measured ? v.error_mean : std::nan(""));
      measures.emplace_back(std::string(c.name) + "_mismatch_rate", v.measured ? v.mismatch_rate : std::nan(""));
    }
  return measures;
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
