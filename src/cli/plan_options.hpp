#pragma once
// The options suite and claims share (which plan, on which heightfields, at which scale, view
// angles, threads and repetitions), turned into the plan's typed settings, and the measurement
// pass with a progress line.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli/common_options.hpp"
#include "cli/progress.hpp"
#include "experiment/measurement_session.hpp"
#include "experiment/plan_runner.hpp"
#include "experiment/suite_plan.hpp"

namespace heightmarch::cli {

// What suite and claims both take: which plan, on which heightfields (the builtins, the user's
// depth maps or both), at which scale and view angles, threads and repetitions.
struct PlanOptions {
  bool quick = false;
  std::string heightmap;     // depth map files, comma-separated, each perhaps with its own reading
  MapOptions map;            // how the --heightmap files are read, where their entries do not say
  bool no_builtins = false;  // the --heightmap files alone
  std::vector<int> threads;  // thread counts (0: all cores); none given: 1 and all cores
  int repetitions = 5;
  std::optional<double> scale;
  std::string view_angles;           // NEAR-FAR degrees; empty: the default view's
  std::optional<ViewSet> views;      // the window (common_options.hpp's --views); none: around
  std::vector<std::string> filters;  // the run's filter, then the compared ones; none: bilinear
};

void add_plan_options(CLI::App& command, PlanOptions& options, const std::string& quick_help);

// The default or quick settings with the options' heightfields, scale, window and its view angles,
// filters (the tutorial's scene: trilinear unless asked), threads and repetitions. Throws
// InputError for values CLI11 cannot check on its own.
PlanSettings plan_settings(const PlanOptions& options, bool glsl);

// In `session` (whose depth maps the caller may have loaded), or a session of its own.
MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced,
                                   MeasurementSession& session);
MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress,
                                   const std::function<void(const TracedRow&)>& on_traced);

}  // namespace heightmarch::cli
