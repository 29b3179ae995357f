#include "experiment/backends.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "baselines/naive_port.hpp"
#include "baselines/structured_pom.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/metrics.hpp"

namespace heightmarch {
namespace {

using Clock = std::chrono::steady_clock;

// A timer around a CPU trace: its wall time.
template <class Trace>
std::function<TraceTime()> wall_timed(Trace trace) {
  return [trace] {
    const Clock::time_point start = Clock::now();
    trace();
    return TraceTime{std::chrono::duration<double>(Clock::now() - start).count(), std::nullopt};
  };
}

// The first ray at which any output of the two differs, or -1.
long long first_difference(const RayBatch& rays, const HitBuffers& a, const HitBuffers& b) {
  std::size_t first = rays.size();
  HitBuffers::for_each_pair(a, b, [&](HitChannel, const auto& x, const auto& y) {
    for (std::size_t i = 0; i < first; ++i)
      if (x[i] != y[i]) first = i;
  });
  return first < rays.size() ? (long long)first : -1;
}

// A Tracer's run of one kind: a technique's kernel (trace), the sampler roofline or the compute
// ceiling, at the configuration's ISA, checked bit for bit against the same run at width 1.
class TracerBackend : public Backend {
 public:
  TracerBackend(Scene::TracerRun run, bool has_accuracy) : run_(run), has_accuracy_(has_accuracy) {}

  void trace(const Configuration& c, Scene& scene, HitBuffers& hits, Measurement& row) override {
    const TraceStats stats = (tracer(c, scene).*run_)(scene.rays, hits);
    if (c.kind == RunKind::trace) row.simd_utilization = stats.simd_utilization();
    // A held-out twin runs the kernel its candidate row checked on the window's every azimuth; a
    // scalar trace to check it again would cost more than the twin itself.
    if (c.isa == Isa::scalar || c.purposes == kPurposeHeldOut) return;
    const long long i = first_difference(scene.rays, hits, scene.reference(c.kind, params(c), run_));
    if (i >= 0)
      row.failure =
          to_string(c.kind) + " output differs from the scalar reference at ray " + std::to_string(i);
  }

  bool has_accuracy() const override { return has_accuracy_; }

  std::function<TraceTime()> timer(const Configuration& c, Scene& scene) override {
    const Tracer& t = tracer(c, scene);
    return wall_timed([&t, &scene, run = run_] { (t.*run)(scene.rays, scene.scratch); });
  }

  void forget() override { tracers_.clear(); }

 private:
  // The roofline samples the positions of a march of 32 layers whatever the configuration says.
  TechniqueParams params(const Configuration& c) const {
    TechniqueParams p = c.params;
    if (run_ == &Tracer::run_sampler_roofline) p.layers = {32.0f, 32.0f};
    return p;
  }

  // One Tracer per configuration, kept for its timed runs (keyed by the plan's object).
  const Tracer& tracer(const Configuration& c, Scene& scene) {
    auto& slot = tracers_[&c];
    if (!slot) slot = std::make_unique<Tracer>(scene.map, params(c), c.isa);
    return *slot;
  }

  Scene::TracerRun run_;
  bool has_accuracy_;
  std::map<const Configuration*, std::unique_ptr<Tracer>> tracers_;
};

// A brought-in loop that never ends is cut off by llvmpipe (or optimised away) and leaves
// garbage, NaN or coordinates far beyond any texture (at 1e6 a float has no texel precision
// left): no figure is made from it.
void check_finite(const Configuration& c, const RayBatch& rays, const HitBuffers& hits) {
  constexpr float kAbsurd = 1e6f;
  std::size_t not_finite = 0, first = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    const bool finite = std::isfinite(hits.u[i]) && std::isfinite(hits.v[i]) && std::isfinite(hits.depth[i]);
    if (!finite || std::fabs(hits.u[i]) > kAbsurd || std::fabs(hits.v[i]) > kAbsurd)
      if (not_finite++ == 0) first = i;
  }
  if (not_finite)
    throw InputError((c.shader_path().empty() ? "GLSL " + to_string(c.params.technique) : c.shader_path()) +
                     ": returned a non-finite uv or depth (or a uv beyond 1e6) for " +
                     std::to_string(not_finite) + " of " + std::to_string(rays.ray_count) +
                     " rays (first: T = " + std::to_string(rays.tx[first]) + "," +
                     std::to_string(rays.ty[first]) + "); an endless loop ends this way in llvmpipe");
}

// The technique (or a brought-in shader) as GLSL, in the worker of its GL target and thread count.
class GlslBackend : public Backend {
 public:
  void trace(const Configuration& c, Scene& scene, HitBuffers& hits, Measurement& row) override {
    GlslRunner& runner = GlslRunner::instance(c.threads, c.gl);
    row.gl = runner.renderer();
    runner.prepare(scene.map, c.params, scene.rays, c.shader_path());
    runner.draw();
    runner.read(hits, row.samples_known);
    row.samples_known = row.samples_known && c.shader_path().empty();
    check_finite(c, scene.rays, hits);
    if (c.shader_path().empty()) return;
    // A loop llvmpipe cut off may leave different garbage each draw.
    HitBuffers again;
    bool known = false;
    runner.draw();
    runner.read(again, known);
    if (const long long i = first_difference(scene.rays, hits, again); i >= 0)
      throw InputError(c.shader_path() +
                       ": returned different hits on two draws of the same rays (first at ray " +
                       std::to_string(i) +
                       "): not deterministic, as a non-finite uv or an endless loop cut off by llvmpipe");
  }

  std::function<TraceTime()> timer(const Configuration& c, Scene& scene) override {
    GlslRunner& runner = GlslRunner::instance(c.threads, c.gl);
    runner.prepare(scene.map, c.params, scene.rays, c.shader_path());
    return [&runner] {
      const GlDrawTime time = runner.draw();
      return TraceTime{time.seconds(runner.renderer()), time};
    };
  }
};

// The naive port of the tutorial's POM, or at the configuration's ISA its auto-vectorised form or
// its Highway form.
// They blend as glm::mix does and round differently from the kernels: checked to be within 0.01
// texel of the technique's reference wherever they took the same samples.
class PortBackend : public Backend {
 public:
  void trace(const Configuration& c, Scene& scene, HitBuffers& hits, Measurement& row) override {
    run(c, scene, hits);
    const HitBuffers& reference = scene.reference(RunKind::trace, c.params, &Tracer::run);
    for (std::size_t i = 0; i < scene.rays.size() && row.failure.empty(); ++i) {
      const float d = uv_error_texels(hits.u[i], hits.v[i], reference.u[i], reference.v[i], scene.map.width,
                                      scene.map.height);
      if (!(d <= 1e-2f) && hits.samples[i] == reference.samples[i])
        row.failure = (c.kind == RunKind::naive     ? std::string("naive port")
                       : c.kind == RunKind::autovec ? c.backend() + " auto-vectorised port"
                                                    : c.backend() + " Highway port") +
                      " differs from the reference by " + std::to_string(d) + " texel at ray " +
                      std::to_string(i);
    }
    hits.depth = reference.depth;  // the port returns uv only
  }

  std::function<TraceTime()> timer(const Configuration& c, Scene& scene) override {
    return wall_timed([&scene, c] { run(c, scene, scene.scratch); });
  }

 private:
  static void run(const Configuration& c, const Scene& scene, HitBuffers& hits) {
    const LayerSpec& l = c.params.layers;
    if (c.kind == RunKind::autovec)
      autovec_pom(scene.map, scene.rays, l.min_layers, l.max_layers, c.params.scale, c.isa, hits);
    else if (c.kind == RunKind::highway)
      highway_pom(scene.map, scene.rays, l.min_layers, l.max_layers, c.params.scale, c.isa, hits);
    else
      naive_pom(scene.map, scene.rays, l.min_layers, l.max_layers, c.params.scale, hits);
  }
};

// The hand-written POM's structure on Google Highway's ops at the configuration's ISA's Highway
// target, checked bit for bit against the technique's scalar reference (its hits are the same).
class StructuredBackend : public Backend {
 public:
  void trace(const Configuration& c, Scene& scene, HitBuffers& hits, Measurement& row) override {
    kernel(c, scene).run(scene.rays, hits);
    const long long i =
        first_difference(scene.rays, hits, scene.reference(RunKind::trace, c.params, &Tracer::run));
    if (i >= 0)
      row.failure =
          "the structured Highway POM differs from the scalar reference at ray " + std::to_string(i);
  }

  std::function<TraceTime()> timer(const Configuration& c, Scene& scene) override {
    const HighwayStructuredPom& k = kernel(c, scene);
    return wall_timed([&k, &scene] { k.run(scene.rays, scene.scratch); });
  }

  void forget() override { kernels_.clear(); }

 private:
  const HighwayStructuredPom& kernel(const Configuration& c, Scene& scene) {
    auto& slot = kernels_[&c];
    if (!slot) slot = std::make_unique<HighwayStructuredPom>(scene.map, c.params, c.isa);
    return *slot;
  }

  std::map<const Configuration*, std::unique_ptr<HighwayStructuredPom>> kernels_;
};

// The exact reference itself (its float pass at the configuration's ISA): its accuracy is zero by
// definition; its speed is what is measured.
class ExactBackend : public Backend {
 public:
  void trace(const Configuration& c, Scene& scene, HitBuffers& hits, Measurement&) override {
    hits = scene.exact(c.params);
  }

  std::function<TraceTime()> timer(const Configuration& c, Scene& scene) override {
    auto& slot = references_[&c];
    if (!slot) slot = std::make_unique<ExactReference>(scene.map, c.params, c.isa);
    const ExactReference& r = *slot;
    return wall_timed([&r, &scene, visibility = visibility_for(c.params.technique)] {
      r.run(scene.rays, visibility, scene.scratch);
    });
  }

  void forget() override { references_.clear(); }

 private:
  std::map<const Configuration*, std::unique_ptr<ExactReference>> references_;
};

// The machine's own speed, the control scripts/compare sets the other rows against: a loop no
// commit of heightmarch changes, of a fixed number of steps per ray, over the batch's rays in
// blocks on the configuration's threads. Each block is one chain of dependent 64-bit
// multiply-xorshift steps: bound by the multiplier's latency, so no compiler flag or ISA can
// vectorise, reorder or shorten it, and its time follows the cores' clock and sharing alone.
class CalibrationBackend : public Backend {
 public:
  void trace(const Configuration&, Scene& scene, HitBuffers& hits, Measurement& row) override {
    hits.resize(scene.rays.size());  // no hits: nothing to check or measure but the time
    row.samples_known = false;
  }

  bool has_accuracy() const override { return false; }

  std::function<TraceTime()> timer(const Configuration&, Scene& scene) override {
    return wall_timed([this, rays = scene.rays.ray_count] { run(rays); });
  }

 private:
  static constexpr std::size_t kStepsPerRay = 16, kBlockRays = 4096;

  void run(std::size_t rays) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, rays, kBlockRays),
        [this](const tbb::blocked_range<std::size_t>& r) {
          std::uint64_t x = r.begin() | 1;
          for (std::size_t i = 0; i < r.size() * kStepsPerRay; ++i) {
            x ^= x >> 29;
            x *= 0xbf58476d1ce4e5b9ull;
          }
          sink_.fetch_xor(x, std::memory_order_relaxed);  // the chain's result is used: never optimised away
        });
  }

  std::atomic<std::uint64_t> sink_{0};
};

}  // namespace

std::unique_ptr<Backend> make_backend(RunKind kind) {
  switch (kind) {
    case RunKind::trace:
      return std::make_unique<TracerBackend>(&Tracer::run, true);
    case RunKind::roofline:
      return std::make_unique<TracerBackend>(&Tracer::run_sampler_roofline, false);
    case RunKind::ceiling:
      return std::make_unique<TracerBackend>(&Tracer::run_compute_ceiling, false);
    case RunKind::glsl:
      return std::make_unique<GlslBackend>();
    case RunKind::naive:
    case RunKind::autovec:
    case RunKind::highway:
      return std::make_unique<PortBackend>();
    case RunKind::highway_structured:
      return std::make_unique<StructuredBackend>();
    case RunKind::exact:
      return std::make_unique<ExactBackend>();
    case RunKind::calibration:
      return std::make_unique<CalibrationBackend>();
  }
  throw std::logic_error("no backend for run kind " + to_string(kind));
}

}  // namespace heightmarch
