#pragma once
// How long a plan's measurement pass takes, estimated before it runs from a short calibration
// (suite --dry-run): every configuration measured once on a small version of its view (every sweep
// at one angle) and the plan's first heightfield, the way the run measures it (its accuracy pass,
// a repetition), then its traces scaled to its view's rays. A rough figure: each map's and each
// angle's own cost per ray is not in it.
#include <cstddef>
#include <vector>

#include "experiment/measurement_session.hpp"

namespace heightmarch {

// Rays of a calibration scene: a frame scaled to about this many, or as many fresh rays drawn like
// a view whose size is not its own to change (a pose file, a rays file).
inline constexpr std::size_t kCalibrationRays = 16384;

struct RunEstimate {
  double seconds = 0;              // the measurement pass: accuracy passes, timed rounds, scenes
  double calibration_seconds = 0;  // what the calibration took
  std::size_t calibrated = 0;      // configurations it measured
};

// The estimate for `plan`, whose views check_inputs() made (`views`), at `repetitions` timed
// repetitions of at least `min_seconds` each, measured in `session` (its depth maps and GL workers
// reused). A configuration's time is its calibration's accuracy pass and `repetitions` of its
// calibration's repetition, each with its traces grown to its view's rays; each scene (heightfield
// and view) adds the making of its view (as long as check_inputs() took), its exact reference and
// the scalar references its ISA rows are checked against, scaled to its rays. Throws what
// measuring the configurations throws.
RunEstimate estimate_run(const std::vector<Configuration>& plan, const std::vector<ViewRays>& views,
                         int repetitions, double min_seconds, MeasurementSession& session);

}  // namespace heightmarch
