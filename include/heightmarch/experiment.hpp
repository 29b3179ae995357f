#pragma once
// One measured run: a scene (depth map + rays), a technique on one backend, its hits timed
// and compared with the exact ones. Shared by the CLI's trace, glsl, suite and claims commands.
#include <functional>
#include <string>
#include <vector>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/metrics.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"
#include "heightmarch/trace.hpp"

namespace heightmarch {

struct Scene {
  std::string heightfield;  // "builtin:bricks" or a path
  DepthMap map;
  std::string view;         // describe(ViewSpec) or "rays:FILE"
  RayBatch rays;
  bool rays_from_file = false;
};

struct RunResult {
  std::string backend;      // the ISA ("avx512", ...) or "glsl"
  int threads = 1;
  HitBuffers hits;
  TraceStats stats;
  bool samples_known = true;  // false for a brought-in shader, which cannot count its samples
  double seconds = 0.0;     // median time of one trace of the whole batch
  int repetitions = 0;
  ErrorSummary errors;
  std::vector<float> uv_error;  // per ray, batch order
  double rays_per_second() const;
  double samples_per_second() const;
};

// A scene: the heightfield ("builtin:NAME" or a path) seen from a view.
Scene make_scene(const std::string& heightfield, int resolution, std::uint64_t seed, Convention convention,
                 const ViewSpec& view, int tile_size = kDefaultTileSize);

// The same depth map seen from another view.
void set_view(Scene& scene, const ViewSpec& view, int tile_size = kDefaultTileSize);

// The exact hits of a scene (and the light's exact visibility from them).
HitBuffers exact_hits(const Scene& scene, const TechniqueParams& params);

// Runs `once` at least once, then again until min_seconds have passed (at most 50 times);
// returns the median time of one run and sets repetitions.
double median_seconds(const std::function<void()>& once, double min_seconds, int& repetitions);

// Traces with the packet kernels of one ISA under the current thread limit, timed over
// repetitions (at least one, until min_seconds have passed, at most 50), then measured.
RunResult run_cpu(const Scene& scene, const HitBuffers& exact, const TechniqueParams& params, Isa isa,
                  int threads, double min_seconds);

// Fills errors and uv_error from hits (for runs traced elsewhere, e.g. GLSL).
void measure(const Scene& scene, const HitBuffers& exact, const TechniqueParams& params, RunResult& run);

// The metrics JSON of SPEC section 5 with the run's configuration and provenance.
std::string metrics_json(const Scene& scene, const TechniqueParams& params, const RunResult& run);

// A short human summary, a few lines.
std::string summary_text(const Scene& scene, const TechniqueParams& params, const RunResult& run);

// hits.exr, error.png, render.png, metrics.json (and rays.csv for rays from a file) in dir.
void write_run_outputs(const std::string& dir, const Scene& scene, const TechniqueParams& params,
                       const RunResult& run, const HitBuffers& exact);

}  // namespace heightmarch
