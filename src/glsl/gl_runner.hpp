#pragma once
// The GL side of GlslRunner, in heightmarch-glsl-worker only: the one draw path of every GL path,
// on a GL 3.3 core context that GlContext made (OSMesa or EGL: only that differs). See
// heightmarch/glsl_runner.hpp for the brought-in shaders' contract.
#include <memory>
#include <optional>
#include <string>

#include "glsl/gl_context.hpp"
#include "glsl/screen_layout.hpp"
#include "heightmarch/gl_target.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

// One draw's time, both ways: the wall time of the draw and its glFinish in the worker, and the
// GPU's own by a GL_TIME_ELAPSED query around the draw (none where the query answers nothing).
struct DrawTimes {
  double wall_seconds = 0;
  std::optional<double> timer_seconds;
};

class GlRunner {
 public:
  // Takes the current context (make_gl_context) and loads its GL functions.
  explicit GlRunner(std::unique_ptr<GlContext> context);
  ~GlRunner();
  GlRunner(const GlRunner&) = delete;
  GlRunner& operator=(const GlRunner&) = delete;

  const GlRenderer& renderer() const { return renderer_; }

  // The depth map and the rays stay in the context until replaced, so a prepare on the same scene
  // uploads neither again; the rays as the client laid them out (screen_layout.hpp).
  void set_depth_map(const DepthMap& map);
  void set_rays(const DrawnRays& rays);
  // The program of the technique, or of the brought-in shader when shader_path is not empty,
  // compiled and linked (or taken from the last 64 kept); InputError for a brought-in shader's
  // errors. Needs no depth map nor rays, so it runs under its own deadline.
  void compile(const TechniqueParams& params, const std::string& shader_path);
  // The rest of GlslRunner's prepare for the program last compiled, on the depth map and rays last
  // set (both must have been): uniforms, wrap mode, precomputed textures.
  void prepare(const TechniqueParams& params);
  // Fills the hits with a NaN sentinel, which read() finds where a fragment was discarded.
  void clear_hits();
  DrawTimes draw();
  void read(HitBuffers& hits, bool& samples_known) const;

 private:
  std::unique_ptr<GlContext> context_;
  struct State;
  std::unique_ptr<State> state_;
  GlRenderer renderer_;
};

}  // namespace heightmarch
