#pragma once
// What the suite and claims commands share.
#include <functional>
#include <string>
#include <vector>

#include "cli/progress.hpp"
#include "heightmarch/suite_plan.hpp"

namespace heightmarch::cli {

// Comma-separated depth map files.
std::vector<HeightfieldSource> extra_heightfields(const std::string& list);

MeasuredPlan measure_with_progress(const std::vector<Configuration>& plan, const PlanSettings& settings,
                                   Progress& progress, const std::function<void(const TracedRow&)>& on_traced);

// claims.md and claims.json from the rows' claims figures; prints the verdicts.
void write_claims(const std::string& dir, const MeasuredPlan& run, const PlanSettings& settings);

}  // namespace heightmarch::cli
