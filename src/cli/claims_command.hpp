#pragma once
// What heightmarch suite shares with heightmarch claims: claims.md and claims.json.
#include <string>

#include "claims/claims.hpp"
#include "experiment/recommendation.hpp"
#include "experiment/suite_plan.hpp"

namespace heightmarch::cli {

// claims.md and claims.json from the claims' figures (ClaimsCollector), with the recommendation
// over the run's rows; prints the verdicts.
void write_claims(const std::string& dir, const ClaimsData& data, const PlanSettings& settings,
                  const Recommendation& recommendation);

}  // namespace heightmarch::cli
