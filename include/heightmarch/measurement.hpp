#pragma once
// The measurement pass: runs each configuration of a plan once for its accuracy (checked against
// the scalar reference before anything is timed), then times every timed configuration in
// interleaved rounds, and returns one typed row per configuration.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "heightmarch/configuration.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/metrics.hpp"

namespace heightmarch {

struct Measurement {
  Configuration config;
  int id = 0;                  // position in the plan
  int depth_map_width = 0, depth_map_height = 0;
  std::size_t rays = 0;        // real rays (padding excluded)
  std::uint64_t samples = 0;   // height samples of one trace (deterministic)
  bool samples_known = true;   // false for a brought-in shader
  double simd_utilization = 1.0;
  // Seconds the precomputed textures of the row's technique (its registry row's needs: the cone
  // map, the min-depth pyramid) took to build, once per depth map and wrap: apart from the
  // trace's time; none for techniques that need none, and for rows without a technique.
  std::optional<double> precompute_seconds;
  std::optional<ErrorSummary> errors;  // none for roofline runs
  std::vector<double> seconds;         // per repetition: one trace of the whole batch; empty if untimed
  std::string render_image, error_image, cost_image;  // gallery rows: paths relative to the run directory
  std::string failure;         // non-empty: not measured (e.g. differs from the scalar reference)

  // Per repetition, and their median, min and max.
  std::vector<double> rays_per_second() const;
  std::vector<double> samples_per_second() const;
};

struct Spread {
  double median = 0, min = 0, max = 0;
};
Spread spread_of(std::vector<double> values);  // all zero for an empty list

// What the pass hands to a consumer that needs more than the row (images, per-ray outputs).
struct TracedRow {
  const Measurement& row;
  const DepthMap& map;
  const RayBatch& rays;
  const HitBuffers& hits;
  const HitBuffers& exact;
  const std::vector<float>& uv_error;  // per ray, batch order
};

struct MeasureOptions {
  int repetitions = 5;              // timed rounds (at least one)
  double min_seconds = 0.04;        // per repetition: traces repeat until this much time passed
  std::function<void(const TracedRow&)> on_traced;  // after a row's accuracy is measured
  // Progress: what runs, how many of how many (accuracy and timing steps together).
  std::function<void(const std::string& what, std::size_t done, std::size_t total)> progress;
};

// How busy the machine was while the pass timed CPU work.
struct MachineLoad {
  double before[3] = {0, 0, 0}, after[3] = {0, 0, 0};  // 1, 5, 15 minute load averages
  double other_cpu_share = 0;  // share of all cores' time used by other processes while timing
  bool busy = false;
  std::vector<std::string> busy_reasons;
};

struct MeasuredPlan {
  std::vector<Measurement> rows;
  MachineLoad load;
  int repetitions = 0;
  double min_seconds = 0;
};

// Single configurations outside a plan (what heightmarch-bench times): depth maps, scenes, exact
// hits and scalar references are built on first use and kept until forget_scenes().
class MeasurementSession {
 public:
  MeasurementSession();
  ~MeasurementSession();

  // A row with the configuration's accuracy, checked against the scalar reference first (a
  // difference is the row's failure); on_traced, if set, sees the hits.
  Measurement measure(const Configuration& config, int id = 0,
                      const std::function<void(const TracedRow&)>& on_traced = {});

  // One trace of the configuration's whole batch, for a timer to call repeatedly (after
  // measure()); prepares what it needs (the Tracer, the GLSL program) when called. Each call
  // returns the seconds of that trace: wall time around a CPU trace, the GLSL worker's own time
  // of a draw (without the round trip to it).
  std::function<double()> trace_once(const Configuration& config);

  void forget_scenes();  // frees every scene but the depth maps

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The runs measure_plan makes of a plan, which its progress counts: one for each configuration's
// accuracy, and `repetitions` for each timed one.
std::size_t plan_runs(const std::vector<Configuration>& plan, int repetitions);

// Runs the plan. Configurations that share a heightfield and view share one scene and one set
// of exact hits; round r times each timed configuration of a scene before round r + 1 starts.
// Throws InputError for bad input (files, shaders); a kernel that differs from its scalar
// reference is recorded as the row's failure and not timed.
MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options);

}  // namespace heightmarch
