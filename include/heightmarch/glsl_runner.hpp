#pragma once
// The techniques as GLSL (src/glsl/) in Mesa's OSMesa (llvmpipe), offscreen, on the same rays
// and parameters as the CPU kernels.
//
// Brought-in shaders (--shader FILE): the file defines LearnOpenGL's
//   vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
// and may use the harness's uniforms `sampler2D depthMap`, `float heightScale` (also spelled
// `height_scale`, the tutorial's name), `float numLayers`, `float minLayers`, `float maxLayers`
// (numLayers = maxLayers, from --layers). Lines of the file that declare these uniforms, and a
// #version line, are dropped so a tutorial's shader pasted as it is compiles. Its depth is the
// depth map at the returned uv; its sample count is unknown.
#include <memory>
#include <string>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

class GlslRunner {
 public:
  // The process's one GL 3.3 core context. llvmpipe reads LP_NUM_THREADS once, when the first
  // context is created, so the thread count is fixed for the process: asking later for another
  // count throws. threads <= 0: all cores.
  static GlslRunner& instance(int threads);

  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  int threads() const { return threads_; }

  // Uploads the depth map and the rays and builds the program (the technique's, or the
  // brought-in shader's when shader_path is not empty). Throws InputError for compile errors,
  // with the brought-in file's line numbers.
  void prepare(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
               const std::string& shader_path = "");

  // One draw over every ray, finished (glFinish). The first draw after prepare() also
  // JIT-compiles the shader: time the ones after it.
  void draw();

  // Reads the hits of the last draw back, in batch order (samples: -1 cast for unknown).
  void read(HitBuffers& hits, bool& samples_known) const;

  ~GlslRunner();

 private:
  explicit GlslRunner(int threads);
  struct State;
  std::unique_ptr<State> state_;
  std::string renderer_, version_;
  int threads_;
};

}  // namespace heightmarch
