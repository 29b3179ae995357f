#pragma once
// One measured configuration as the measurement pass returns it (a typed row), the statistics of
// its repetitions, and what the pass hands to a consumer of its traced rows.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "experiment/configuration.hpp"
#include "heightmarch/gl_target.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/metrics.hpp"
#include "io/colour_difference.hpp"

namespace heightmarch {

struct Measurement {
  Configuration config;
  int id = 0;  // position in the plan
  int depth_map_width = 0, depth_map_height = 0;
  std::size_t rays = 0;       // real rays (padding excluded)
  std::uint64_t samples = 0;  // height samples of one trace (deterministic)
  bool samples_known = true;  // false for a brought-in shader
  double simd_utilization = 1.0;
  // Seconds the precomputed textures of the row's technique (its registry row's needs: the cone
  // map, the min-depth pyramid) took to build, once per depth map and wrap: apart from the
  // trace's time; none for techniques that need none, and for rows without a technique.
  std::optional<double> precompute_seconds;
  std::optional<ErrorSummary> errors;  // none for roofline runs
  // The shaded image against the exact one supersampled (config.supersample > 0).
  std::optional<ImageError> image_error;
  std::vector<double> seconds;  // per repetition: one trace of the whole batch; empty if untimed
  // GLSL rows: what the worker's context was (the renderer every figure of the row is named by),
  // and each repetition's draws timed both ways (GlDrawTime): `seconds` holds the figure
  // GlDrawTime::seconds() picks, the wall time on a software renderer, the timer query on a GPU.
  std::optional<GlRenderer> gl;
  std::vector<double> gl_wall_seconds, gl_timer_seconds;  // timer: empty where the driver answered none
  // Gallery rows: paths relative to the run directory; the colour difference map where the row
  // has an image error, and the exact render supersampled on the exact row (whose difference is
  // the resolve's own).
  std::string render_image, error_image, cost_image, difference_image, reference_image;
  std::string failure;  // non-empty: not measured (e.g. differs from the scalar reference)

  // Per repetition, and their median, min and max.
  std::vector<double> rays_per_second() const;
  std::vector<double> samples_per_second() const;
};

// One trace's time, as a timer returns it: its seconds (for GLSL the figure GlDrawTime::seconds()
// picks) and, for GLSL, the draw's two clocks.
struct TraceTime {
  double seconds = 0;
  std::optional<GlDrawTime> gl;
};

struct Spread {
  double median = 0, min = 0, max = 0;
};
Spread spread_of(std::vector<double> values);  // all zero for an empty list

// A row's shaded image beside the exact one supersampled, and their colour difference per pixel
// (over the pixels the row's view has a ray at: `compared`).
struct ShadedComparison {
  LinearImage render;
  const LinearImage* reference = nullptr;
  std::vector<float> delta_e;
  std::vector<std::uint8_t> compared;
};

// What the pass hands to a consumer that needs more than the row (images, per-ray outputs).
struct TracedRow {
  const Measurement& row;
  const DepthMap& map;
  const RayBatch& rays;
  const HitBuffers& hits;
  const HitBuffers& exact;             // level 0's
  const HitBuffers& surface_read;      // on the surface the row's samples read (exact where that is level 0)
  const std::vector<float>& uv_error;  // per ray, batch order: texels, against level 0's exact hit
  const std::vector<float>&
      search_error;                  // the same against the surface read's (uv_error where that is level 0)
  std::function<Shading()> shading;  // how its images shade its hits (the albedo built on first use)
  const ShadedComparison* shaded = nullptr;  // where the row has an image error
};

}  // namespace heightmarch
