#pragma once
// What a suite run (or a claims run) measures, as one typed plan of configurations: the default
// plan, the quick one, and the claims' part of either.
#include <string>
#include <vector>

#include "heightmarch/claims.hpp"
#include "heightmarch/configuration.hpp"
#include "heightmarch/measurement.hpp"

namespace heightmarch {

struct PlanSettings {
  std::string name;                            // "default", "quick"
  std::vector<HeightfieldSource> heightfields;
  std::vector<LayerSpec> layer_specs;          // of the matrix (and GLSL)
  int view_size = 1024;                        // default view side, pixels
  int sweep_size = 128;                        // sweep views: side, pixels
  std::vector<double> sweep_angles;            // degrees
  int gallery_width = 512, gallery_height = 384;
  Isa best_isa = Isa::scalar;
  std::vector<Isa> isas;                       // every ISA the CPU runs
  int threads = 1;                             // all cores, or --threads
  bool glsl = true;
  int repetitions = 5;
  double min_seconds = 0.04;                   // per repetition
  bool large_maps = true;                      // P2's rows on the builtins at kLargeMapSide
};

// The default or quick settings; extra files are measured beside the builtins.
PlanSettings suite_settings(bool quick, const std::vector<HeightfieldSource>& extra, int threads, bool glsl);

// Everything a suite run measures: the matrix, POM-32 at every ISA and thread count, GLSL, the
// roofline, the naive port, sweeps, the gallery and the claims' rows.
std::vector<Configuration> suite_plan(const PlanSettings& settings);

// The claims' rows alone (what `heightmarch claims` runs): every row each claim declares
// (claims.hpp) on every heightfield, sweeps untimed, and with large_maps the large-map rows on
// the builtins at kLargeMapSide.
std::vector<Configuration> claims_plan(const PlanSettings& settings);

}  // namespace heightmarch
