#pragma once
// MeasurementSession: the measurement pass one configuration at a time.
#include <functional>
#include <memory>
#include <vector>

#include "experiment/measurement.hpp"

namespace heightmarch {

// A view of a plan, the rays it holds (padding aside) and the seconds it took to make them, as
// check_inputs() made them.
struct ViewRays {
  ViewSpec view;
  std::size_t rays = 0;
  double seconds = 0;
};

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
  // Every input the plan reads, opened and checked once, before anything is measured or written:
  // the one check that a real run and its dry run share (suite, claims, trace, glsl,
  // heightmarch-bench and their dry runs), so a dry run fails where the run would, with its line.
  // Every depth map decoded (a file with its channel and convention, a builtin made) and kept; every
  // view's rays made and checked, then dropped (pose and rays files parsed, the finite check of
  // every batch, the memory budget); every GL target of its GLSL rows started (its path and device
  // probed, a context made) and kept, and a brought-in shader compiled. Throws InputError (the run's
  // own), std::runtime_error for a GL worker that cannot start. Returns each view with its rays.
  std::vector<ViewRays> check_inputs(const std::vector<Configuration>& plan);

  void forget_scenes();  // frees every scene but the depth maps

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace heightmarch
