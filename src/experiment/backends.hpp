#pragma once
// The backends of the measurement pass: one per run kind (configuration.hpp's list), each able
// to trace a configuration once for its accuracy (checked against its reference first) and to
// time it.
#include <functional>
#include <memory>

#include "experiment/measurement.hpp"
#include "experiment/scene.hpp"

namespace heightmarch {

class Backend {
 public:
  virtual ~Backend() = default;

  // The accuracy run: the configuration's rays traced once into hits and checked against the
  // backend's reference (a difference is the row's failure, and the row is not timed); fills
  // what the backend knows of the row (SIMD use, whether its samples are counted). Throws
  // InputError for bad input (a brought-in shader's).
  virtual void trace(const Configuration& config, Scene& scene, HitBuffers& hits, Measurement& row) = 0;

  // Whether the hits have an accuracy to measure (the anchors' do not: the roofline returns sums,
  // the compute ceiling hits a flat depth 1).
  virtual bool has_accuracy() const { return true; }

  // Prepares one trace of the configuration's whole batch for a timer to call repeatedly; each
  // call returns the seconds of that trace (wall time around a CPU trace; the GLSL worker's own
  // time of a draw, without the round trip to it).
  virtual std::function<double()> timer(const Configuration& config, Scene& scene) = 0;

  // Frees what it keeps per configuration (tracers), with the scenes.
  virtual void forget() {}
};

// The backend of a run kind.
std::unique_ptr<Backend> make_backend(RunKind kind);

}  // namespace heightmarch
