#include "heightmarch/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string_view>
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

// The rays of each azimuth sector or view-angle band that has any: p99, wrong rate and its
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
    group.wrong_rate = double(wrong) / double(e.size());
    group.wrong_ci = clopper_pearson(double(wrong) / design, double(e.size()) / design);
    const std::size_t rank = std::size_t(std::ceil(0.99 * double(e.size())));
    std::nth_element(e.begin(), e.begin() + (rank - 1), e.end());
    group.p99 = e[rank - 1];
    out.push_back(group);
  }
  return out;
}

// The statistics of one distribution's measured rays (of a batch of `views` views).
ErrorDistribution distribution_of(const std::vector<MeasuredRay>& measured, std::uint32_t views,
                                  bool grouped) {
  ErrorDistribution d;
  if (measured.empty()) return d;
  d.measured = true;
  d.rays = measured.size();
  double sum = 0, sum_sq = 0;
  std::size_t wrong = 0;
  std::vector<float> errors;
  errors.reserve(measured.size());
  for (const MeasuredRay& r : measured) {
    sum += r.error;
    sum_sq += double(r.error) * r.error;
    wrong += r.error > 1.0f;
    errors.push_back(r.error);
  }
  const double n = double(measured.size());
  d.mean = sum / n;
  d.rms = std::sqrt(sum_sq / n);
  d.wrong_rate = double(wrong) / n;
  std::sort(errors.begin(), errors.end());
  d.p50 = percentile(errors, 50);
  d.p95 = percentile(errors, 95);
  d.p99 = percentile(errors, 99);
  d.max = errors.back();
  d.p50_ci = percentile_interval(errors, measured, views, 50, d.p50);
  d.p95_ci = percentile_interval(errors, measured, views, 95, d.p95);
  d.p99_ci = percentile_interval(errors, measured, views, 99, d.p99);
  const double design = design_effect(measured, views, 1.0f);
  d.effective_rays = n / design;
  d.wrong_ci = clopper_pearson(double(wrong) / design, d.effective_rays);
  if (grouped) {
    d.by_azimuth = group_errors(measured, true, kAzimuthSectors, 360.0 / kAzimuthSectors,
                                -180.0 / kAzimuthSectors, design);
    d.by_view_angle = group_errors(measured, false, kAngleBands, kViewAngleBand, 0.0, design);
  }
  return d;
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

double pixel_offset(double du, double dv, double du_dx, double dv_dx, double du_dy, double dv_dy) {
  const double det = du_dx * dv_dy - du_dy * dv_dx;
  if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) return std::nan("");
  return std::hypot((dv_dy * du - du_dy * dv) / det, (du_dx * dv - dv_dx * du) / det);
}

ErrorSummary summarize_errors(const RayBatch& rays, const HitBuffers& hits, const ExactHits& exact,
                              int map_width, int map_height, Writes written,
                              std::vector<float>* per_ray_error) {
  ErrorSummary s;
  const HitBuffers& level0 = exact.level0;
  if (per_ray_error) per_ray_error->assign(rays.size(), 0.0f);
  // The rays measured, each with its azimuth sector and view-angle band (once: every distribution
  // groups by them).
  std::vector<std::size_t> measured;
  std::vector<std::uint8_t> sector, band;
  measured.reserve(rays.ray_count);
  double depth_sum = 0, samples = 0;
  std::size_t real = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    ++real;
    samples += hits.samples[i];
    if (hits.discarded[i]) {
      ++s.discarded;
      continue;
    }
    measured.push_back(i);
    // Sector k spans 45 k +- 22.5 degrees of V's azimuth; band b, 15 b to 15 (b + 1) degrees from the normal.
    const double azimuth = std::atan2(double(rays.vy[i]), double(rays.vx[i])) * 180.0 / kPi;
    const double sector_width = 360.0 / kAzimuthSectors;
    sector.push_back(std::uint8_t(int(std::floor((azimuth + 360.0 + 0.5 * sector_width) / sector_width)) %
                                  kAzimuthSectors));
    const double angle = std::acos(std::clamp(double(rays.vz[i]), -1.0, 1.0)) * 180.0 / kPi;
    band.push_back(std::uint8_t(std::min(int(angle / kViewAngleBand), kAngleBands - 1)));
    depth_sum += std::fabs(double(hits.depth[i]) - double(level0.depth[i]));
  }
  s.rays = measured.size();
  s.samples_per_ray = real ? samples / double(real) : 0.0;
  if (measured.empty()) return s;
  const double n = double(measured.size());
  s.depth_error_mean = depth_sum / n;
  // Each distribution in turn (one ray list in memory at a time): the offset between its two hits,
  // in texels of level 0 or in pixels of the ray's footprint (rays without one left out).
  std::vector<MeasuredRay> errors;
  errors.reserve(measured.size());
  for (const ErrorDistributionInfo& d : error_distributions()) {
    const HitBuffers& to = d.between == ErrorBetween::read_level0 ? exact.surface_read : hits;
    const HitBuffers& from = d.between == ErrorBetween::hit_read ? exact.surface_read : level0;
    errors.clear();
    for (std::size_t k = 0; k < measured.size(); ++k) {
      const std::size_t i = measured[k];
      float e;
      if (d.in == ErrorUnit::texels) {
        e = uv_error_texels(to.u[i], to.v[i], from.u[i], from.v[i], map_width, map_height);
      } else {
        const double px =
            pixel_offset(double(to.u[i]) - double(from.u[i]), double(to.v[i]) - double(from.v[i]),
                         rays.du_dx[i], rays.dv_dx[i], rays.du_dy[i], rays.dv_dy[i]);
        if (std::isnan(px)) continue;
        e = float(px);
      }
      if (per_ray_error && d.member == &ErrorSummary::uv) (*per_ray_error)[i] = e;
      errors.push_back({e, rays.view[i], sector[k], band[k]});
    }
    s.*d.member = distribution_of(errors, rays.views, d.grouped);
  }
  // Each output against the exact visibility (the exact hits' shadow: 0 or 1), on the same rays.
  for (const HitChannelInfo& c : hit_channels()) {
    if (!measured_against_visibility(c, written)) continue;
    const std::vector<float>& value = float_channel(hits, c.id);
    double error_sum = 0;
    std::size_t mismatched = 0;
    for (std::size_t i : measured) {
      error_sum += std::fabs(double(value[i]) - double(level0.shadow[i]));
      mismatched += (value[i] >= 0.5f) != (level0.shadow[i] >= 0.5f);
    }
    s.visibility[std::size_t(c.id)] = {true, error_sum / n, double(mismatched) / n};
  }
  return s;
}

const std::vector<ErrorDistributionInfo>& error_distributions() {
  static const std::vector<ErrorDistributionInfo> list = {
#define HEIGHTMARCH_DISTRIBUTION_INFO(member, name, wrong, quantity, unit, wrong_label, between, grouped) \
  {&ErrorSummary::member,                                                                                 \
   #name,                                                                                                 \
   #wrong,                                                                                                \
   quantity,                                                                                              \
   unit,                                                                                                  \
   wrong_label,                                                                                           \
   ErrorBetween::between,                                                                                 \
   std::string_view(unit) == "pixels" ? ErrorUnit::pixels : ErrorUnit::texels,                            \
   grouped},
#define HEIGHTMARCH_NO_FIGURE(...)
      HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_DISTRIBUTION_INFO, HEIGHTMARCH_NO_FIGURE)
#undef HEIGHTMARCH_DISTRIBUTION_INFO
#undef HEIGHTMARCH_NO_FIGURE
  };
  return list;
}

const ErrorDistributionInfo& distribution_named(const std::string& name) {
  for (const ErrorDistributionInfo& d : error_distributions())
    if (d.name == name) return d;
  throw std::out_of_range("no error distribution " + name);
}

namespace {

// The statistics of a distribution's measures, in the list's order: NAME_STATISTIC, then its wrong rate.
constexpr const char* kStatistics[] = {"mean", "rms", "p50", "p95", "p99", "max"};
constexpr double ErrorDistribution::*kStatisticMembers[] = {
    &ErrorDistribution::mean, &ErrorDistribution::rms, &ErrorDistribution::p50,
    &ErrorDistribution::p95,  &ErrorDistribution::p99, &ErrorDistribution::max};

}  // namespace

const std::vector<ErrorMeasure>& error_measure_list() {
  static const std::vector<ErrorMeasure> list = [] {
    std::vector<ErrorMeasure> measures;
    const auto distribution = [&](const std::string& name) {
      const ErrorDistributionInfo& d = distribution_named(name);
      for (const char* statistic : kStatistics)
        measures.push_back(
            {d.measure(statistic), std::string(std::strcmp(statistic, "rms") == 0 ? "RMS" : statistic) + " " +
                                       d.quantity + " (" + d.unit + ")"});
      measures.push_back({d.wrong_name, d.wrong_label + " (share of rays)"});
    };
#define HEIGHTMARCH_DISTRIBUTION_MEASURES(member, name, ...) distribution(#name);
#define HEIGHTMARCH_FIGURE_MEASURE(name, member, label) measures.push_back({#name, label});
    HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_DISTRIBUTION_MEASURES, HEIGHTMARCH_FIGURE_MEASURE)
#undef HEIGHTMARCH_DISTRIBUTION_MEASURES
#undef HEIGHTMARCH_FIGURE_MEASURE
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
  std::vector<std::pair<std::string, double>> measures;
  const auto distribution = [&](const std::string& name) {
    const ErrorDistributionInfo& d = distribution_named(name);
    const ErrorDistribution& values = e.*d.member;
    for (std::size_t k = 0; k < std::size(kStatistics); ++k)
      measures.emplace_back(d.measure(kStatistics[k]),
                            values.measured ? values.*kStatisticMembers[k] : std::nan(""));
    measures.emplace_back(d.wrong_name, values.measured ? values.wrong_rate : std::nan(""));
  };
#define HEIGHTMARCH_DISTRIBUTION_VALUES(member, name, ...) distribution(#name);
#define HEIGHTMARCH_FIGURE_VALUE(name, member, label) measures.emplace_back(#name, e.member);
  HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_DISTRIBUTION_VALUES, HEIGHTMARCH_FIGURE_VALUE)
#undef HEIGHTMARCH_DISTRIBUTION_VALUES
#undef HEIGHTMARCH_FIGURE_VALUE
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

std::vector<float> uv_errors(const RayBatch& rays, const HitBuffers& hits, const HitBuffers& exact,
                             int map_width, int map_height) {
  std::vector<float> out(rays.size(), 0.0f);
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i) && !hits.discarded[i])
      out[i] = uv_error_texels(hits.u[i], hits.v[i], exact.u[i], exact.v[i], map_width, map_height);
  return out;
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
