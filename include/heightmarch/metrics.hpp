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
  double p99 = 0, wrong_rate = 0;
  Interval wrong_ci;
};
inline constexpr int kAzimuthSectors = 8;
inline constexpr double kViewAngleBand = 15.0;

// One error per measured ray in one unit (texels of level 0, or pixels of the ray's footprint),
// against one exact hit: its statistics over the rays.
struct ErrorDistribution {
  // Whether any ray had it: a batch without a pixel grid (a rays file) has no footprint,
  // so no error in pixels.
  bool measured = false;
  std::size_t rays = 0;
  double mean = 0, rms = 0, p50 = 0, p95 = 0, p99 = 0, max = 0;
  // The share of rays more than one unit off: on a wrong surface (texels), on a wrong pixel (pixels).
  double wrong_rate = 0;
  // 95% confidence intervals (docs/measures.md#confidence): of p50, p95 and p99 from order
  // statistics, of the wrong rate by Clopper-Pearson, each on the rays' effective number (the rays
  // over the design effect of the views they were traced in: neighbouring pixels err alike).
  // effective_rays: the wrong rate's.
  Interval p50_ci, p95_ci, p99_ci, wrong_ci;
  double effective_rays = 0;
  std::vector<ErrorGroup> by_azimuth, by_view_angle;  // groups with rays only; the grouped ones'
};

// A technique's hits are measured against two exact hits (docs/measures.md#accuracy-per-ray): the
// level-0 surface's (the heightfield's, exact_hits()) and that of the surface its samples read
// (FilteredExactReference: under trilinear filtering the blend of two mip levels at the ray's
// level of detail; level 0's where it reads level 0, and then the same hits).
struct ExactHits {
  const HitBuffers& level0;
  const HitBuffers& surface_read;
};

// The error distributions of the hit, one row each, and the single figures:
// DISTRIBUTION(ErrorSummary member, name, wrong-rate name, quantity, unit, wrong label, against,
// grouped), with `against` the two exact hits it is the distance of (the technique's hit, level 0's
// and the surface read's: ExactHits) and `grouped` whether it is broken down by azimuth and view
// angle; each gives the measures NAME_mean, NAME_rms, NAME_p50, NAME_p95, NAME_p99, NAME_max
// ("p99 QUANTITY (UNIT)") and its wrong rate ("WRONG LABEL (share of rays)").
// FIGURE(name, ErrorSummary member, label).
// With those of each output measured against the light's visibility, NAME_error_mean ("mean LABEL
// error") and NAME_mismatch_rate ("NAME mismatch (share)"), they are the one list of the error
// measures: measurements.json (which carries their names and labels), metrics.json,
// measurements.csv, bench.json, heightmarch-bench's counters and the report use them.
// - uv_error: the hit's distance to level 0's exact hit in texels of level 0 (what it shows of the
//   heightfield); pixel_error: the same through the ray's pixel footprint (what a player sees).
// - search_error, search_pixel_error: to the exact hit on the surface the ray read (what layers
//   buy); under bilinear filtering, or for a technique that reads level 0, the same as the above.
// - filter_bias, filter_pixel_bias: from level 0's exact hit to the surface read's (what
//   mipmapping costs; 0 where the surface read is level 0). The hit's error is their sum, as
//   vectors.
#define HEIGHTMARCH_HIT_MEASURES(DISTRIBUTION, FIGURE)                                                    \
  DISTRIBUTION(uv, uv_error, wrong_surface_rate, "uv error", "texels", "wrong surface", hit_level0, true) \
  FIGURE(depth_error_mean, depth_error_mean, "mean depth error")                                          \
  DISTRIBUTION(pixels, pixel_error, wrong_pixel_rate, "pixel error", "pixels", "wrong pixel", hit_level0, \
               true)                                                                                      \
  DISTRIBUTION(search, search_error, search_wrong_surface_rate, "search error", "texels",                 \
               "wrong surface of the surface read", hit_read, false)                                      \
  DISTRIBUTION(search_pixels, search_pixel_error, search_wrong_pixel_rate, "search error", "pixels",      \
               "wrong pixel of the surface read", hit_read, false)                                        \
  DISTRIBUTION(bias, filter_bias, filter_wrong_surface_rate, "filter bias", "texels",                     \
               "filter's wrong surface", read_level0, false)                                              \
  DISTRIBUTION(bias_pixels, filter_pixel_bias, filter_wrong_pixel_rate, "filter bias", "pixels",          \
               "filter's wrong pixel", read_level0, false)

// Which two hits a distribution measures the distance of.
enum class ErrorBetween { hit_level0, hit_read, read_level0 };
enum class ErrorUnit { texels, pixels };

struct ErrorSummary {
  std::size_t rays = 0;  // real rays measured (not discarded)
  std::size_t discarded = 0;
#define HEIGHTMARCH_DISTRIBUTION_MEMBER(member, ...) ErrorDistribution member;
#define HEIGHTMARCH_FIGURE_MEMBER(name, member, label) double member = 0;
  HEIGHTMARCH_HIT_MEASURES(HEIGHTMARCH_DISTRIBUTION_MEMBER, HEIGHTMARCH_FIGURE_MEMBER)
#undef HEIGHTMARCH_DISTRIBUTION_MEMBER
#undef HEIGHTMARCH_FIGURE_MEMBER
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
};

// One row of the distributions' list.
struct ErrorDistributionInfo {
  ErrorDistribution ErrorSummary::*member;
  std::string name;        // "pixel_error": its measures NAME_p99, ...
  std::string wrong_name;  // "wrong_pixel_rate"
  std::string quantity, unit, wrong_label;
  ErrorBetween between;
  ErrorUnit in;
  bool grouped;
  std::string measure(const std::string& statistic) const {
    return name + "_" + statistic;
  }  // "pixel_error_p99"
  // Its wrong rate's interval where a group carries it: "wrong_pixel_ci" (the rate's name, _rate
  // replaced).
  std::string wrong_ci_name() const { return wrong_name.substr(0, wrong_name.rfind("_rate")) + "_ci"; }
};
const std::vector<ErrorDistributionInfo>& error_distributions();
const ErrorDistributionInfo& distribution_named(const std::string& name);  // throws std::out_of_range

// Clopper-Pearson: the exact 95% interval of a rate from `successes` of `trials` (either may be
// fractional: an effective number of rays).
Interval clopper_pearson(double successes, double trials);
// The 95% interval of the p-quantile (p in (0, 1)) as fractions of the sorted values' ranks, from
// the binomial law of the order statistics over `trials` (effective) values.
Interval quantile_rank_interval(double p, double trials);
// The regularized incomplete beta function I_x(a, b), a, b > 0, x in [0, 1].
double incomplete_beta(double a, double b, double x);

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

// A uv offset (du, dv) in pixels of the footprint (du_dx, dv_dx) x (du_dy, dv_dy) (RayBatch's
// gradients: how T moves to the next pixel in x and in y): its length in the pixel's own axes,
// |J^-1 (du, dv)| with J = [du_dx du_dy; dv_dx dv_dy]. NaN for a footprint that spans no area (a
// ray without a pixel grid: zero gradients).
double pixel_offset(double du, double dv, double du_dx, double dv_dx, double du_dy, double dv_dy);

// Errors per ray (uv error in texels against level 0's exact hit; 0 for padding and discarded
// rays) and their summary; `written`: the optional outputs the hits carry (a technique's registry
// row's), measured against the exact ones (level 0's).
ErrorSummary summarize_errors(const RayBatch& rays, const HitBuffers& hits, const ExactHits& exact,
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
// Per ray, batch order: the hit's distance to `exact`'s in texels of level 0 (0 for padding and
// discarded rays), as summarize_errors measures it.
std::vector<float> uv_errors(const RayBatch& rays, const HitBuffers& hits, const HitBuffers& exact,
                             int map_width, int map_height);

double share_within_one_layer_step(const RayBatch& rays, const HitBuffers& hits,
                                   const std::vector<float>& uv_error, const TechniqueParams& params,
                                   int map_width, int map_height);

}  // namespace heightmarch
