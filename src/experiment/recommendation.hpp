#pragma once
// Which technique and layer count to ship: at a declared backend (a CPU ISA and thread count, or
// GLSL), the configuration with the least measured time per ray among those that meet both an
// error-percentile bound and a wrong-surface bound, for each heightfield and as one setting for
// all of them (a shader runs one setting on every material); the preprocessing its technique
// needs (cone map, min-depth pyramid) shown beside it, amortised over a stated number of frames.
// One implementation for the suite, the claims and `heightmarch recommend`
// (docs/recommendation.md says why the default targets are what they are).
#include <optional>
#include <string>
#include <vector>

#include "experiment/configuration.hpp"
#include "experiment/measurement.hpp"

namespace heightmarch {

// The uv error percentiles a run measures; the bound applies to one of them.
enum class ErrorPercentile { p50, p95, p99, max };
inline constexpr ErrorPercentile kErrorPercentiles[] = {ErrorPercentile::p50, ErrorPercentile::p95,
                                                        ErrorPercentile::p99, ErrorPercentile::max};
std::string to_string(ErrorPercentile percentile);     // "p99": how options and people name it
std::string measure_name(ErrorPercentile percentile);  // "uv_error_p99": how result files name it

struct RecommendationTarget {
  ErrorPercentile percentile = ErrorPercentile::p99;
  double uv_error_texels = 0.5;       // that percentile of the uv error at most this
  double wrong_surface_rate = 0.005;  // the share of rays more than one texel off at most this
  int frames = 3600;                  // preprocessing amortised over this many frames (a minute at 60 fps)
};
// Throws InputError for bounds that are negative or not finite, or frames below 1.
void validate(const RecommendationTarget& target);
std::string describe(const RecommendationTarget& target);  // "p99 <= 0.5 texel, wrong surface <= 0.5%"

// Where a recommendation's time is measured: a CPU ISA at a thread count, or GLSL (llvmpipe).
struct RecommendationBackend {
  RunKind kind = RunKind::trace;  // trace or glsl
  Isa isa = Isa::scalar;          // trace only
  int threads = 1;
  std::string backend() const;  // "avx512", "glsl": as rows name it
  std::string name() const;     // "avx512, 2 threads"
  friend bool operator==(const RecommendationBackend&, const RecommendationBackend&) = default;
};

// A measured configuration as the recommendation reads it: the typed fields of a run's row (a
// Measurement in the suite and claims, a row of measurements.json in `heightmarch recommend`).
struct Candidate {
  int id = 0;               // the row's id in its run
  std::string heightfield;  // its label, unique within the run
  int depth_map_width = 0, depth_map_height = 0;
  RecommendationBackend backend;
  bool grid = false;  // of the technique x layers grid or the claims: its CPU backend is a declared one
  Technique technique = Technique::pom;
  LayerSpec layers;
  double uv_error[4] = {0, 0, 0, 0};  // by ErrorPercentile
  double wrong_surface_rate = 0;
  double samples_per_ray = 0;
  std::size_t rays = 0;         // real rays of one trace of the view
  std::vector<double> seconds;  // one trace of the view, per repetition (round)
  std::optional<double> precompute_seconds;

  double error(ErrorPercentile p) const { return uv_error[int(p)]; }
};

// The rows a recommendation may choose from: timed, measured, unfailed technique rows on the
// default view (CPU kernels and GLSL; brought-in shaders excluded) of the technique x layers grid,
// the claims and GLSL.
std::vector<Candidate> candidates(const std::vector<Measurement>& rows);

// A configuration's time: per round, the mean over its heightfields of the seconds per ray.
struct Pick {
  Technique technique = Technique::pom;
  LayerSpec layers;
  std::vector<Candidate> rows;          // one per heightfield, in the run's order
  std::vector<double> seconds_per_ray;  // per round
  Spread time() const { return spread_of(seconds_per_ray); }
  std::string label() const;  // "relief 16", "maxmip"
};

// The answer for one heightfield, or for all of them as one setting (heightfield empty).
struct Answer {
  std::string heightfield;                // empty: one setting for every heightfield
  int settings = 0, meeting = 0;          // configurations measured on it (on all), and meeting the target
  std::optional<Pick> choice, runner_up;  // the fastest meeting the target, and the next
  std::optional<Spread> runner_up_ratio;  // per round: the runner-up's time over the choice's
  std::optional<Pick> closest;            // none meets: the one nearest to meeting it
};

struct BackendRecommendation {
  RecommendationBackend backend;
  std::vector<Answer> per_heightfield;
  Answer all_heightfields;
};

struct Recommendation {
  RecommendationTarget target;
  std::vector<BackendRecommendation> backends;
};

// The declared backends are those of the grid's CPU rows, and GLSL at their thread counts. Throws
// InputError for a target validate() refuses.
Recommendation recommend(const std::vector<Candidate>& candidates, const RecommendationTarget& target);

// recommendation.json (docs/measurements.md), and for people a few lines per backend.
inline constexpr int kRecommendationFormatVersion = 1;
std::string recommendation_json(const Recommendation& recommendation);
std::string recommendation_text(const Recommendation& recommendation);
std::string recommendation_markdown(const Recommendation& recommendation);  // a table, for claims.md

}  // namespace heightmarch
