#pragma once
// MeasurementSession: the measurement pass one configuration at a time.
#include <functional>
#include <memory>
#include <vector>

#include "experiment/measurement.hpp"

namespace heightmarch {

// Single configurations outside a plan (what heightmarch-bench times): depth maps, scenes, exact
// hits and scalar references are built on first use and kept until forget_scenes().
class MeasurementSession {
 public:
  MeasurementSession();
  ~MeasurementSession();

  // A row with the configuration's accuracy, checked against the scalar reference first (a
  // difference is the row's failure); on_traced, if set, sees the hits.
  Measurement measure(const Configuration& config, int id = 0,
                      const std::function<void(const TracedRow&)>& on_traced = {});

  // One trace of the configuration's whole batch, for a timer to call repeatedly (after
  // measure()); prepares what it needs (the Tracer, the GLSL program) when called. Each call
  // returns the time of that trace: wall time around a CPU trace, the GLSL worker's own times of
  // a draw (without the round trip to it).
  std::function<TraceTime()> trace_once(const Configuration& config);

  // The depth map of a source, decoded (or made) on first use and kept.
  const DepthMap& depth_map(const HeightfieldSource& source);
  // Decodes every depth map file the plan names, each once: a bad one is one line before any work.
  void load_depth_maps(const std::vector<Configuration>& plan);

  void forget_scenes();  // frees every scene but the depth maps

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace heightmarch
