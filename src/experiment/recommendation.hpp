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

// The error percentiles a run measures; the bound applies to one of them.
enum class ErrorPercentile { p50, p95, p99, max };
inline constexpr ErrorPercentile kErrorPercentiles[] = {ErrorPercentile::p50, ErrorPercentile::p95,
                                                        ErrorPercentile::p99, ErrorPercentile::max};
std::string to_string(ErrorPercentile percentile);  // "p99": how options and people name it

// A target bounds a row's search error, its hit against the exact hit on the surface its samples
// read (level 0 under bilinear filtering, the blend of two mip levels under trilinear: metrics.hpp),
// in texels of level 0 or in pixels of each ray's footprint: what the layers buy, the same measure
// under both filters. The filter's bias (what mipmapping costs) is reported beside it.
struct RecommendationTarget {
  ErrorPercentile percentile = ErrorPercentile::p99;
  ErrorUnit unit = ErrorUnit::pixels;
  double max_error = 0.5;         // that percentile of the search error at most this, in the unit
  double max_wrong_rate = 0.005;  // the share of rays more than one unit off at most this
  int frames = 3600;              // preprocessing amortised over this many frames (a minute at 60 fps)
};
// Throws InputError for bounds that are negative or not finite, or frames below 1.
void validate(const RecommendationTarget& target);
std::string describe(const RecommendationTarget& target);  // "p99 <= 0.5 pixel, wrong pixel <= 0.5%"
std::string to_string(ErrorUnit unit);                     // "texels", "pixels"
ErrorUnit parse_error_unit(const std::string& name);       // throws InputError
// The error distributions of a unit (metrics.hpp): the search error (the target's), the filter's
// bias and the hit's error against level 0 (what the player sees of the heightfield).
struct UnitDistributions {
  const ErrorDistributionInfo &search, &bias, &total;
};
UnitDistributions distributions_in(ErrorUnit unit);
std::string measure_name(const RecommendationTarget& target);  // "search_pixel_error_p99"

// Where a recommendation's time is measured: a CPU ISA at a thread count, or GLSL on a renderer,
// each under one filter (a shader that samples level 0 and one that samples a mip chain are two
// answers, side by side).
struct RecommendationBackend {
  RunKind kind = RunKind::trace;  // trace or glsl
  Isa isa = Isa::scalar;          // trace only
  int threads = 1;
  // glsl: its renderer's label (GlRenderer::label(): another renderer is another backend); empty
  // for a run from before rows recorded it.
  std::string gl;
  Filter filter = Filter::bilinear;
  std::string backend() const;  // "avx512", "glsl": as rows name it
  // "avx512, 2 threads, bilinear", "glsl (llvmpipe, LLVM 15.0.6, 256 bits; OSMesa), 2 threads, trilinear"
  std::string name() const;
  friend bool operator==(const RecommendationBackend&, const RecommendationBackend&) = default;
};

// One distribution's figures as a target reads them: its percentiles and its wrong rate, each with
// its 95% interval (metrics.hpp; the max's is the max itself).
struct Figures {
  double values[4] = {0, 0, 0, 0};  // by ErrorPercentile
  Interval intervals[4];
  double wrong_rate = 0;
  Interval wrong_ci;
  double error(ErrorPercentile p) const { return values[int(p)]; }
  Interval error_ci(ErrorPercentile p) const { return intervals[int(p)]; }
};
Figures figures_of(const ErrorDistribution& distribution);

// A row's accuracy in one unit: its search error (what a target bounds), the filter's bias (its
// surface read's exact hit from level 0's; zero under bilinear) and its error against level 0.
struct Accuracy {
  Figures search, bias, total;
  std::size_t rays = 0;
  double error(ErrorPercentile p) const { return search.error(p); }
  Interval error_ci(ErrorPercentile p) const { return search.error_ci(p); }
  double wrong_rate() const { return search.wrong_rate; }
};
// Throws InputError where the row has no errors in the unit (pixels of rays without a pixel grid).
Accuracy accuracy_of(const ErrorSummary& errors, ErrorUnit unit);

// Whether the target's search bounds hold, and whether the filter's bias alone misses the target
// while being at least the search error at its percentile: then more layers do not change what a
// player sees ("filter-dominated").
bool meets(const Accuracy& accuracy, const RecommendationTarget& target);
bool filter_dominated(const Accuracy& accuracy, const RecommendationTarget& target);

// A measured configuration as the recommendation reads it: the typed fields of a run's row (a
// Measurement in the suite and claims, a row of measurements.json in `heightmarch recommend`),
// with its accuracy on the held-out view set where its twin was measured.
struct Candidate {
  int id = 0;               // the row's id in its run
  std::string heightfield;  // its label, unique within the run
  int depth_map_width = 0, depth_map_height = 0;
  RecommendationBackend backend;
  bool grid = false;  // of the technique x layers grid or the claims: its CPU backend is a declared one
  Technique technique = Technique::pom;
  LayerSpec layers;
  Filter filter = Filter::bilinear;  // what its samples were asked to read with (its backend's)
  Accuracy selection;                // on the window, where the choice is made
  std::optional<Accuracy> held_out;  // on the held-out set, where it is checked
  int held_out_id = -1;
  double samples_per_ray = 0;
  std::size_t rays = 0;         // real rays of one trace of the window
  std::vector<double> seconds;  // one trace of the window, per repetition (round)
  std::optional<double> precompute_seconds;
};

// The rows a recommendation may choose from: timed, measured, unfailed technique rows on the
// window (CPU kernels and GLSL; brought-in shaders excluded) of the technique x layers grid under
// each filter, the claims and GLSL, each joined to its held-out twin (purpose held-out) where there
// is one, their accuracy in the unit. Throws InputError as accuracy_of.
std::vector<Candidate> candidates(const std::vector<Measurement>& rows, ErrorUnit unit);

// A configuration's time: per round, the mean over its heightfields of the seconds per ray.
struct Pick {
  Technique technique = Technique::pom;
  LayerSpec layers;
  std::vector<Candidate> rows;          // one per heightfield, in the run's order
  std::vector<double> seconds_per_ray;  // per round
  Spread time() const { return spread_of(seconds_per_ray); }
  std::string label() const;  // "relief 16", "maxmip"
};

// How much slower one pick is than another, in the statistic that ranks them: the ratio of their
// median times (so a slower pick never reads faster), and the spread of the per-round ratios
// (including 1: not distinguishable on this machine).
struct TimeRatio {
  double ratio = 1;
  Spread per_round;
  bool distinguishable() const { return per_round.min > 1.0 || per_round.max < 1.0; }
};

// A setting that misses the target by little: the larger of its measures over their bounds
// (1.08: 8% over), on the figures that decided (the held-out ones where they miss).
struct NearMiss {
  Pick pick;
  double margin = 0;
  std::string measure;  // "p99", "wrong surface"
};
// A near miss misses a bound by less than this share of it.
inline constexpr double kNearMissShare = 0.2;

// The answer for one heightfield, or for all of them as one setting (heightfield empty). A
// setting meets the target where its figures on the window do and, where its held-out twins were
// measured, theirs do too.
struct Answer {
  std::string heightfield;                   // empty: one setting for every heightfield
  int settings = 0, meeting = 0;             // configurations measured on it (on all), and meeting the target
  bool held_out_checked = false;             // every setting's rows had their held-out twins
  std::optional<Pick> choice, runner_up;     // the fastest meeting the target, and the next
  std::optional<TimeRatio> runner_up_ratio;  // the runner-up's time over the choice's
  std::vector<Pick> failed_held_out;         // faster than the choice, met the target on the window only
  std::optional<NearMiss> near_miss;         // the fastest that misses by less than kNearMissShare, if faster
  std::optional<Pick> closest;               // none meets: the one nearest to meeting it
  // Under trilinear: the choice (or the nearest) has a heightfield where the filter's bias alone
  // misses the target and outweighs the search error (filter_dominated).
  bool filter_dominated = false;
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

// The declared backends are those of the grid's CPU rows under each filter, and GLSL at their
// thread counts and filters. Throws InputError for a target validate() refuses.
Recommendation recommend(const std::vector<Candidate>& candidates, const RecommendationTarget& target);

// recommendation.json (docs/measurements.md; format 2 added the held-out figures, their intervals
// and the near miss; format 3 the target's unit, the search error it bounds with the filter's bias
// beside it, a backend per filter and filter-dominated answers), and for people a few lines per
// backend.
inline constexpr int kRecommendationFormatVersion = 3;
std::string recommendation_json(const Recommendation& recommendation);
std::string recommendation_text(const Recommendation& recommendation);
std::string recommendation_markdown(const Recommendation& recommendation);  // a table, for claims.md

}  // namespace heightmarch
