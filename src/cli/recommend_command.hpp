#pragma once
// What suite and claims share with heightmarch recommend: the recommendation's target options and
// its recommendation.json.
#include <CLI/CLI.hpp>
#include <string>

#include "experiment/recommendation.hpp"

namespace heightmarch::cli {

// The recommendation's target (--percentile, --max-error, --max-wrong-surface, --frames), on the
// commands that write recommendation.json.
void add_target_options(CLI::App& command, RecommendationTarget& target);

// recommendation.json in dir; prints the recommendation.
void write_recommendation(const std::string& dir, const Recommendation& recommendation);

}  // namespace heightmarch::cli
