#pragma once
// What the suite and claims commands share.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "claims/claims_collector.hpp"
#include "cli/common_options.hpp"
#include "cli/progress.hpp"
#include "heightmarch/recommendation.hpp"
#include "heightmarch/suite_plan.hpp"

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
  std::string view_angles;  // NEAR-FAR degrees; empty: the default view's
};

void add_plan_options(CLI::App& command, PlanOptions& options, const std::string& quick_help);

// The default or quick settings with the options' heightfields, scale, view angles, threads and
// repetitions. Throws InputError for values CLI11 cannot check on its own.
PlanSettings plan_settings(const PlanOptions& options, bool glsl);

// The recommendation's target (--percentile, --max-error, --max-wrong-surface, --frames), on the
// commands that write recommendation.json.
void add_target_options(CLI::App& command, RecommendationTarget& target);

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced);

// claims.md and claims.json from the claims' figures (ClaimsCollector), with the recommendation
// over the run's rows; prints the verdicts.
void write_claims(const std::string& dir, const ClaimsData& data, const PlanSettings& settings,
                  const Recommendation& recommendation);

// recommendation.json in dir; prints the recommendation.
void write_recommendation(const std::string& dir, const Recommendation& recommendation);

}  // namespace heightmarch::cli
