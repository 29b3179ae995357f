#pragma once
// What a suite run (or a claims run) measures, as one typed plan of configurations: the default
// plan, the quick one, and the claims' part of either.
#include <cstdint>
#include <map>
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

// The claims' rows alone (what `heightmarch claims` runs): every claim technique (steep, relief,
// POM, secant, cone; maxmip) at the claims' layer specs on the default view, plain and
// offset-limited parallax on sweep views at the claims' angles, steep, relief and POM at 8-32 and
// 32 on near-normal sweep views, and with large_maps P2's rows on the builtins at kLargeMapSide.
std::vector<Configuration> claims_plan(const PlanSettings& settings);

// The figures the claims' rules read: observe() sees each traced row (the measurement pass's
// on_traced) and keeps the per-ray figures of the rows with the claims purpose; data() joins them
// to the rows' summaries and speeds.
class ClaimsCollector {
 public:
  void observe(const TracedRow& traced);
  ClaimsData data(const std::vector<Measurement>& rows) const;

 private:
  // What the rows of one scene (heightfield, view, scale, wrap) share: which rays hit where the
  // depth map changes sharply (top decile of |grad D|), smoothly (bottom half), or on a thin feature.
  struct SceneFeatures {
    HeightfieldSource heightfield;
    ViewSpec view;
    float scale = 0;
    Wrap wrap = Wrap::repeat;
    std::vector<std::uint8_t> sharp, smooth, thin;
    bool has_spread = false;  // the top decile's |grad D| exceeds the bottom half's
  };
  SceneFeatures features_;
  std::map<int, ClaimFigure::PerRay> per_row_;  // by the row's id (its position in the plan)
};

}  // namespace heightmarch
