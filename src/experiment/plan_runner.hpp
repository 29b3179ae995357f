#pragma once
// The measurement pass: runs each configuration of a plan once for its accuracy (checked against
// the scalar reference before anything is timed), then times every timed configuration in
// interleaved rounds, and returns one typed row per configuration.
#include <functional>
#include <string>
#include <vector>

#include "experiment/machine_load.hpp"
#include "experiment/measurement.hpp"
#include "experiment/measurement_session.hpp"

namespace heightmarch {

struct MeasureOptions {
  int repetitions = 5;        // timed rounds (at least one)
  double min_seconds = 0.04;  // per repetition: traces repeat until this much time passed
  std::function<void(const TracedRow&)> on_traced;  // after a row's accuracy is measured
  // Progress: what runs, how many of the plan_runs() runs are done.
  std::function<void(const std::string& what, std::size_t done, std::size_t total)> progress;
};

struct MeasuredPlan {
  std::vector<Measurement> rows;
  MachineLoad load;
  int repetitions = 0;
  double min_seconds = 0;
};

// The runs measure_plan makes of a plan, which its progress counts: one for each configuration's
// accuracy, and `repetitions` for each timed one.
std::size_t plan_runs(const std::vector<Configuration>& plan, int repetitions);

// Runs the plan. Configurations that share a heightfield and view share one scene and one set
// of exact hits; round r times each timed configuration of a scene before round r + 1 starts.
// Throws InputError for bad input (files, shaders); a kernel that differs from its scalar
// reference is recorded as the row's failure and not timed.
MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options);
// The same in a session of the caller's, whose depth maps it may have loaded first (a bad file is
// then its error before any work, and no file is decoded twice).
MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options,
                          MeasurementSession& session);

}  // namespace heightmarch
