#pragma once
// What a suite run measures: the default plan and the quick one, shared by suite and claims.
#include <string>
#include <vector>

#include "heightmarch/isa.hpp"

namespace heightmarch::cli {

struct SuitePlan {
  bool quick = false;
  std::vector<std::string> heightfields;  // "builtin:NAME" or paths
  std::vector<std::string> layer_specs;
  int resolution = 512;                   // builtin depth maps
  int bench_view_size = 1024;             // benchmark view side
  double bench_min_time = 0.2;            // seconds per benchmark
  int sweep_size = 128;                   // sweep view side for error vs angle
  std::vector<std::string> sweep_heightfields;
  int gallery_width = 512, gallery_height = 384;
  int claims_view_size = 384, claims_sweep_size = 128;
};

// extra_heightmaps: comma-separated files added to the builtins.
SuitePlan make_suite_plan(bool quick, const std::string& extra_heightmaps);

// Writes claims.md and claims.json into dir (claims_command.cpp).
void write_claims(const std::string& dir, const SuitePlan& plan, Isa isa, int threads);

}  // namespace heightmarch::cli
