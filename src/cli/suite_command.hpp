#pragma once
// What the suite and claims commands share.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "cli/progress.hpp"
#include "claims/claims_collector.hpp"
#include "heightmarch/suite_plan.hpp"

namespace heightmarch::cli {

// What suite and claims both take: which plan, on which heightfields, threads and repetitions.
struct PlanOptions {
  bool quick = false;
  std::string heightmap;  // extra depth map files, comma-separated
  int threads = 0;        // 0: all cores
  int repetitions = 5;
};

void add_plan_options(CLI::App& command, PlanOptions& options, const std::string& quick_help);

// The default or quick settings with the options' heightfields, threads and repetitions.
PlanSettings plan_settings(const PlanOptions& options, bool glsl);

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced);

// claims.md and claims.json from the claims' figures (ClaimsCollector); prints the verdicts.
void write_claims(const std::string& dir, const ClaimsData& data, const PlanSettings& settings);

}  // namespace heightmarch::cli
