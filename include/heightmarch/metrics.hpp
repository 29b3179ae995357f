#pragma once
// Error and speed measures (docs/measures.md) of a technique's hits against the exact ones.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

// Per ray: |(uv - T*) * (W, H)| in texels, unwrapped coordinates.
float uv_error_texels(float u, float v, float exact_u, float exact_v, int width, int height);

// Height samples of the batch's real rays (padding excluded).
std::uint64_t total_samples(const RayBatch& rays, const HitBuffers& hits);

// A 95% confidence interval.
struct Interval {
  double low = 0, high = 0;
};

// Rays of one azimuth sector of V (45 degrees wide, centred on 0, 45, ..., 315) or one band of
// view angles from the normal (15 degrees wide): where a measure varies across a view set.
struct ErrorGroup {
  double from = 0, to = 0;  // degrees
  std::size_t rays = 0;
  double p99 = 0, wrong_surface_rate = 0;
  Interval wrong_surface_ci;
};
inline constexpr int kAzimuthSectors = 8;
inline constexpr double kViewAngleBand = 15.0;

struct ErrorSummary {
  std::size_t rays = 0;  // real rays measured (not discarded)
  std::size_t discarded = 0;
  double mean = 0, rms = 0, p50 = 0, p95 = 0, p99 = 0, max = 0;  // uv error, texels
  double wrong_surface_rate = 0;                                 // share of rays with uv error > 1 texel
  double depth_error_mean = 0;
  double samples_per_ray = 0;  // over all real rays, discarded included
  // Per output measured against the light's visibility (hits.hpp), where the technique writes it
  // (`measured`): mean |value - exact visibility| and the share of rays whose value, thresholded
  // at 0.5, disagrees with the exact visibility.
  struct VisibilityError {
    bool measured = false;
    double error_mean = 0, mismatch_rate = 0;
  };
  std::array<VisibilityError, kHitChannelCount> visibility{};  // by HitChannel
  // Layered techniques: the share of rays within one layer's texture step of the exact hit.
  std::optional<double> within_one_layer_step;
  // 95% confidence intervals (docs/measures.md#confidence): of p50, p95 and p99 from order
  // statistics, of the wrong-surface rate by Clopper-Pearson, each on the rays' effective number
  // (the rays over the design effect of the tiles they were traced in: neighbouring pixels err
  // alike). effective_rays: the wrong-surface rate's.
  Interval p50_ci, p95_ci, p99_ci, wrong_surface_ci;
  double effective_rays = 0;
  std::vector<ErrorGroup> by_azimuth, by_view_angle;  // groups with rays only
};

// Clopper-Pearson: the exact 95% interval of a rate from `successes` of `trials` (either may be
// fractional: an effective number of rays).
Interval clopper_pearson(double successes, double trials);
// The 95% interval of the p-quantile (p in (0, 1)) as fractions of the sorted values' ranks, from
// the binomial law of the order statistics over `trials` (effective) values.
Interval quantile_rank_interval(double p, double trials);
// The regularized incomplete beta function I_x(a, b), a, b > 0, x in [0, 1].
double incomplete_beta(double a, double b, double x);

// The measures of the hit, one row each: X(name, ErrorSummary member, label). With those of each
// output measured against the light's visibility, NAME_error_mean ("mean LABEL error") and
// NAME_mismatch_rate ("NAME mismatch (share)"), they are the one list of the error measures:
// measurements.json (which carries their names and labels), metrics.json, measurements.csv,
// bench.json, heightmarch-bench's counters and the report use them.
#define HEIGHTMARCH_HIT_MEASURES(X)                                          \
  X(uv_error_mean, mean, "mean uv error (texels)")                           \
  X(uv_error_rms, rms, "RMS uv error (texels)")                              \
  X(uv_error_p50, p50, "p50 uv error (texels)")                              \
  X(uv_error_p95, p95, "p95 uv error (texels)")                              \
  X(uv_error_p99, p99, "p99 uv error (texels)")                              \
  X(uv_error_max, max, "max uv error (texels)")                              \
  X(wrong_surface_rate, wrong_surface_rate, "wrong surface (share of rays)") \
  X(depth_error_mean, depth_error_mean, "mean depth error")

struct ErrorMeasure {
  std::string name, label;
};
// Every error measure's name and label, in order; their names comma-separated (as a Google
// Benchmark context value carries them).
const std::vector<ErrorMeasure>& error_measure_list();
std::string error_measure_names();

// Every error measure of a row as (name, value), in error_measure_list()'s order; NaN for an
// output's measures where the row's technique does not write it.
std::vector<std::pair<std::string, double>> error_measures(const ErrorSummary& errors);

// The measures the row has (error_measures without the NaN ones), as Google Benchmark counters.
std::vector<std::pair<std::string, double>> error_counters(const ErrorSummary& errors);

// Errors per ray (0 for padding and discarded rays) and their summary; `written`: the optional
// outputs the hits carry (a technique's registry row's), measured against the exact ones.
ErrorSummary summarize_errors(const RayBatch& rays, const HitBuffers& hits, const HitBuffers& exact,
                              int map_width, int map_height, Writes written,
                              std::vector<float>* per_ray_error = nullptr);

// The texture step of one layer along a ray, in texels: s V.xy / V.z / N scaled by the map's
// size, with N the layer count at V.z (layer_count, technique.hpp).
double layer_step_texels(const LayerSpec& layers, float scale, float vx, float vy, float vz, int map_width,
                         int map_height);

// Whether a uv error is beyond one layer step (with a relative and an absolute slack for rounding).
inline bool beyond_one_layer_step(double uv_error, double layer_step) {
  return uv_error > layer_step * (1.0 + 1e-4) + 1e-6;
}

// Share of measured rays whose uv error is at most the texture step of one layer along their own
// ray: stair-stepping's bound.
double share_within_one_layer_step(const RayBatch& rays, const HitBuffers& hits,
                                   const std::vector<float>& uv_error, const TechniqueParams& params,
                                   int map_width, int map_height);

}  // namespace heightmarch
