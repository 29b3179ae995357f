#include "heightmarch/metrics.hpp"

#include <algorithm>
#include <array>
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

constexpr double kPi = 3.14159265358979323846;

// Nearest-rank percentile of sorted values.
double percentile(const std::vector<float>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const std::size_t rank = std::size_t(std::ceil(p / 100.0 * double(sorted.size())));
  return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

// A measured ray: its error, its view (the cluster of design_effect), its azimuth sector and
// view-angle band.
struct MeasuredRay {
  float error;
  std::uint32_t cluster;
  std::uint8_t sector, band;
};

constexpr int kAngleBands = int(90.0 / kViewAngleBand);

// How much less a share over these rays (of those with error > threshold) tells than one over as
// many independent rays: its variance over a simple random sample's, at least 1. Rays are not
// independent draws: neighbouring pixels err alike, and the rays of one view of a set share its
// one draw of azimuth and offset. So each view (RayBatch::view: a cell of a set around the surface,
// a frame, a pose, or a tile of a single view) is one cluster, and the variance is that of a
// stratified sample of clusters, each stratum two views numbered 2k and 2k + 1 (neighbours in
// azimuth and angle: collapsed strata, as one draw per stratum leaves no spread within it to
// measure, and the neighbour's stands in for it, a little too large).
double design_effect(const std::vector<MeasuredRay>& rays, std::uint32_t views, float threshold) {
  std::vector<double> m(views, 0.0), x(views, 0.0);  // rays, and rays over the threshold, per view
  double over = 0;
  for (const MeasuredRay& r : rays) {
    const bool is_over = r.error > threshold;
    m[r.cluster] += 1;
    x[r.cluster] += is_over;
    over += is_over;
  }
  const double n = double(rays.size()), p = over / n;
  if (p <= 0 || p >= 1 || views < 2) return 1.0;
  double variance = 0;
  for (std::uint32_t begin = 0; begin + 1 < views; begin += 2) {
    const std::uint32_t end = views - begin == 3 ? begin + 3 : begin + 2;  // the last takes the odd one out
    double stratum_m = 0, stratum_x = 0, clusters = 0;
    for (std::uint32_t c = begin; c < end; ++c) stratum_m += m[c], stratum_x += x[c], clusters += m[c] > 0;
    if (clusters < 2) continue;
    double sum = 0;
    for (std::uint32_t c = begin; c < end; ++c) {
      if (m[c] == 0) continue;
      const double d = x[c] - stratum_x / stratum_m * m[c];
      sum += d * d;
    }
    variance += clusters / (clusters - 1) * sum;
  }
  return std::max(1.0, variance / (n * n) / (p * (1 - p) / n));
}

// The 95% interval of a percentile of the sorted errors, on the effective number of rays.
Interval percentile_interval(const std::vector<float>& sorted, const std::vector<MeasuredRay>& rays,
                             std::uint32_t views, double p, double value) {
  const double n = double(sorted.size());
  const Interval ranks = quantile_rank_interval(p / 100.0, n / design_effect(rays, views, float(value)));
  const auto at = [&](double fraction) {
    return sorted[std::size_t(std::clamp(std::ceil(fraction * n), 1.0, n)) - 1];
  };
  return {std::min(double(at(ranks.low)), value), std::max(double(at(ranks.high)), value)};
}

// The rays of each azimuth sector or view-angle band that has any: p99, wrong-surface rate and its
// interval (on the rays' effective number, at the whole set's design effect).
std::vector<ErrorGroup> group_errors(const std::vector<MeasuredRay>& rays, bool by_sector, int groups,
                                     double width, double first, double design) {
  std::vector<std::vector<float>> errors(groups);
  for (const MeasuredRay& r : rays) errors[by_sector ? r.sector : r.band].push_back(r.error);
  std::vector<ErrorGroup> out;
  for (int g = 0; g < groups; ++g) {
    std::vector<float>& e = errors[g];
    if (e.empty()) continue;
    ErrorGroup group;
    group.from = first + g * width;
    group.to = group.from + width;
    group.rays = e.size();
    const std::size_t wrong = std::count_if(e.begin(), e.end(), [](float x) { return x > 1.0f; });
    group.wrong_surface_rate = double(wrong) / double(e.size());
    group.wrong_surface_ci = clopper_pearson(double(wrong) / design, double(e.size()) / design);
    const std::size_t rank = std::size_t(std::ceil(0.99 * double(e.size())));
    std::nth_element(e.begin(), e.begin() + (rank - 1), e.end());
    group.p99 = e[rank - 1];
    out.push_back(group);
  }
  return out;
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
  std::vector<MeasuredRay> measured;
  measured.reserve(rays.ray_count);
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
    // Sector k spans 45 k +- 22.5 degrees of V's azimuth; band b, 15 b to 15 (b + 1) degrees from the normal.
    const double azimuth = std::atan2(double(rays.vy[i]), double(rays.vx[i])) * 180.0 / kPi;
    const double sector_width = 360.0 / kAzimuthSectors;
    const int sector =
        int(std::floor((azimuth + 360.0 + 0.5 * sector_width) / sector_width)) % kAzimuthSectors;
    const double angle = std::acos(std::clamp(double(rays.vz[i]), -1.0, 1.0)) * 180.0 / kPi;
    const int band = std::min(int(angle / kViewAngleBand), kAngleBands - 1);
    measured.push_back({e, rays.view[i], std::uint8_t(sector), std::uint8_t(band)});
    sum += e;
    sum_sq += double(e) * e;
    wrong += e > 1.0f;
    depth_sum += std::fabs(double(hits.depth[i]) - double(exact.depth[i]));
  }
  s.rays = measured.size();
  s.samples_per_ray = real ? samples / double(real) : 0.0;
  if (measured.empty()) return s;
  const double n = double(measured.size());
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
  std::vector<float> errors;
  errors.reserve(measured.size());
  for (const MeasuredRay& r : measured) errors.push_back(r.error);
  std::sort(errors.begin(), errors.end());
  s.p50 = percentile(errors, 50);
  s.p95 = percentile(errors, 95);
  s.p99 = percentile(errors, 99);
  s.max = errors.back();
  s.p50_ci = percentile_interval(errors, measured, rays.views, 50, s.p50);
  s.p95_ci = percentile_interval(errors, measured, rays.views, 95, s.p95);
  s.p99_ci = percentile_interval(errors, measured, rays.views, 99, s.p99);
  const double design = design_effect(measured, rays.views, 1.0f);
  s.effective_rays = n / design;
  s.wrong_surface_ci = clopper_pearson(double(wrong) / design, s.effective_rays);
  s.by_azimuth = group_errors(measured, true, kAzimuthSectors, 360.0 / kAzimuthSectors,
                              -180.0 / kAzimuthSectors, design);
  s.by_view_angle = group_errors(measured, false, kAngleBands, kViewAngleBand, 0.0, design);
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
      measures.emplace_back(std::string(c.name) + "_mismatch_rate",
                            v.measured ? v.mismatch_rate : std::nan(""));
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
    within +=
        !beyond_one_layer_step(uv_error[i], layer_step_texels(params.layers, params.scale, rays.vx[i],
                                                              rays.vy[i], rays.vz[i], map_width, map_height));
    ++measured;
  }
  return measured ? double(within) / double(measured) : 0.0;
}

}  // namespace heightmarch
