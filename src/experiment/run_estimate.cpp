#include "experiment/run_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include "heightmarch/exact.hpp"
#include "heightmarch/tracer.hpp"

namespace heightmarch {
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A small version of a view, as the run sees it: a frame (or each tutorial frame) scaled to about
// kCalibrationRays pixels at its angles, every sweep at kCalibrationSweepDegrees (one calibration
// for the sweeps of every angle); fresh rays drawn like a view whose size is its file's.
constexpr float kCalibrationSweepDegrees = 45.0f;
ViewSpec calibration_view(const ViewSpec& view) {
  ViewSpec small = view;
  if (view.kind == ViewSpec::Kind::sweep) small.theta_degrees = kCalibrationSweepDegrees;
  if (view.fresh_rays > 0 || view.kind == ViewSpec::Kind::poses || view.kind == ViewSpec::Kind::rays_file) {
    small.fresh_rays = kCalibrationRays;
    return small;
  }
  const double frames = view.kind == ViewSpec::Kind::tutorial ? view.views : 1.0;
  const double scale = std::sqrt(double(kCalibrationRays) / (double(view.width) * view.height * frames));
  if (scale < 1.0) {
    small.width = std::max(kViewCell, int(std::lround(view.width * scale)));
    small.height = std::max(kViewCell, int(std::lround(view.height * scale)));
  }
  return small;
}

// What the run does for a configuration beside its own traces: the exact reference of its scene
// (once per scene and light visibility) and, at an ISA other than scalar, the scalar reference its
// output is checked against (once per scene, kind and parameters): each a configuration of its own.
Configuration exact_of(const Configuration& c) {
  Configuration exact = c;
  exact.kind = RunKind::exact;
  exact.isa = Isa::scalar;
  exact.gl = {};
  exact.shader.reset();
  // What the exact reference depends on: scale, wrap, light, discard, and the light's visibility
  // where the technique writes a shadow factor; not the layers nor the filter.
  exact.params.technique =
      visibility_for(c.params.technique) == LightVisibility::compute ? c.params.technique : Technique::pom;
  exact.params.layers = LayerSpec::fixed(1);
  exact.params.refine.reset();
  exact.params.filter = Filter::bilinear;
  return exact;
}

Configuration reference_of(const Configuration& c) {
  Configuration reference = c;
  reference.isa = Isa::scalar;
  return reference;
}

bool checked_against_scalar(const Configuration& c) {
  return (c.kind == RunKind::trace || c.kind == RunKind::roofline || c.kind == RunKind::ceiling ||
          c.kind == RunKind::highway_structured) &&
         c.isa != Isa::scalar && c.purposes != kPurposeHeldOut;
}

// One configuration's calibration on its calibration scene, at its threads: its accuracy pass, one
// trace and one repetition as the run times it (a warm-up, then traces until min_seconds), whose
// fixed costs (waking threads, a round trip to the GL worker, a busy machine's waits) are the run's.
struct Calibrated {
  Configuration config;  // on the calibration scene
  std::size_t rays = 0;
  double accuracy = 0, trace = 0, repetition = 0;  // seconds
};

class Calibration {
 public:
  Calibration(const HeightfieldSource& heightfield, double min_seconds, MeasurementSession& session)
      : heightfield_(heightfield), min_seconds_(min_seconds), session_(session) {}

  // The calibration of c, measured on first use.
  const Calibrated& of(const Configuration& c) {
    Configuration small = c;
    small.heightfield = heightfield_;
    small.view = calibration_view(c.view);
    for (const Calibrated& k : done_)
      if (k.config.same_measurement(small)) return k;
    // The scene's own costs first (the exact reference, scalar references), so that the
    // configuration's accuracy pass is its own.
    if (small.kind != RunKind::exact) of(exact_of(c));
    if (checked_against_scalar(small)) of(reference_of(c));
    // Measured where it stays: the backends keep what they build for a configuration by its address.
    Calibrated& k = done_.emplace_back(Calibrated{small});
    const Clock::time_point start = Clock::now();
    const Measurement row = session_.measure(k.config);
    k.accuracy = since(start);
    k.rays = row.rays;
    if (row.failure.empty()) {
      const ThreadLimit limit(k.config.threads);
      const Clock::time_point repetition = Clock::now();
      const std::function<TraceTime()> once = session_.trace_once(k.config);
      once();  // the warm-up
      double elapsed = 0;
      for (int runs = 0; runs == 0 || (elapsed < min_seconds_ && runs < kMaxRuns); ++runs) {
        k.trace = once().seconds;
        elapsed = since(repetition);
      }
      k.repetition = since(repetition);
    }
    return k;
  }

  std::size_t count() const { return done_.size(); }

 private:
  static constexpr int kMaxRuns = 100000;  // as the run's repetitions
  HeightfieldSource heightfield_;
  double min_seconds_;
  MeasurementSession& session_;
  std::deque<Calibrated> done_;  // its elements stay where they are as it grows
};

}  // namespace

RunEstimate estimate_run(const std::vector<Configuration>& plan, const std::vector<ViewRays>& views,
                         int repetitions, double min_seconds, MeasurementSession& session) {
  RunEstimate estimate;
  if (plan.empty()) return estimate;
  const Clock::time_point start = Clock::now();
  Calibration calibration(plan.front().heightfield, min_seconds, session);
  // Seconds of a calibrated trace, scaled to a view's rays (at the threads it was calibrated at).
  const auto scaled = [&](double seconds, const Calibrated& k, const Configuration& c) {
    std::size_t rays = 0;
    for (const ViewRays& v : views)
      if (v.view == c.view) rays = v.rays;
    return k.rays ? seconds * double(rays) / double(k.rays) : 0.0;
  };
  // A pass on the configuration's view: the calibration's, plus the traces' work for the rays it
  // has beyond the calibration's.
  const auto grown = [&](double seconds, const Calibrated& k, const Configuration& c) {
    return seconds + std::max(0.0, scaled(k.trace, k, c) - k.trace);
  };
  // Each scene's costs once (its view made, its exact references and its scalar references), each
  // configuration's accuracy pass and timed rounds.
  std::vector<Configuration> once_per_scene;
  const auto first_time = [&](const Configuration& c) {
    if (std::any_of(once_per_scene.begin(), once_per_scene.end(),
                    [&](const Configuration& o) { return o.same_measurement(c); }))
      return false;
    once_per_scene.push_back(c);
    return true;
  };
  for (const Configuration& c : plan) {
    Configuration scene;  // stands for the scene itself: its heightfield and view
    scene.kind = RunKind::calibration;
    scene.heightfield = c.heightfield;
    scene.view = c.view;
    scene.threads = 0;
    if (first_time(scene))
      for (const ViewRays& v : views)
        if (v.view == c.view) estimate.seconds += v.seconds;
    if (c.kind != RunKind::exact && first_time(exact_of(c))) {
      const Calibrated& exact = calibration.of(exact_of(c));
      estimate.seconds += scaled(exact.accuracy, exact, c);
    }
    if (checked_against_scalar(c) && first_time(reference_of(c))) {
      const Calibrated& reference = calibration.of(reference_of(c));
      estimate.seconds += scaled(reference.trace, reference, c);
    }
    // Its accuracy pass (the exact reference its calibration scene held already aside) and its
    // repetitions: the calibration's, the traces grown to its view.
    const Calibrated& k = calibration.of(c);
    estimate.seconds += grown(k.accuracy, k, c);
    const double trace = scaled(k.trace, k, c);
    if (c.timed)
      estimate.seconds += repetitions * (k.repetition - k.trace - std::max(k.trace, min_seconds) + trace +
                                         std::max(trace, min_seconds));
  }
  session.forget_scenes();
  estimate.calibration_seconds = since(start);
  estimate.calibrated = calibration.count();
  return estimate;
}

}  // namespace heightmarch
