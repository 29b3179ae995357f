#pragma once
// The figures the claims' rules read, gathered while the measurement pass traces the claims' rows.
#include <cstdint>
#include <map>
#include <vector>

#include "claims/claims.hpp"
#include "experiment/measurement.hpp"

namespace heightmarch {

// observe() sees each traced row (the measurement pass's on_traced) and keeps the per-ray figures
// of the rows with the claims purpose; data() joins them to the rows' summaries and speeds.
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
