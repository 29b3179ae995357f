#pragma once
// The techniques as GLSL (src/glsl/) in Mesa's OSMesa (llvmpipe), offscreen, on the same rays
// and parameters as the CPU kernels. The GL context lives in a worker process,
// heightmarch-glsl-worker (src/glsl/worker_main.cpp), so only GLSL runs load libOSMesa and
// libLLVM, and each llvmpipe thread count (read once per process) gets its own context.
//
// The worker is found next to the running executable, or at $HEIGHTMARCH_GLSL_WORKER. It runs
// under an OS memory limit derived from the memory budget (memory_budget.hpp) and checks every
// message it is sent (src/glsl/protocol.hpp). A program's compile and link may take 20 s; a draw
// 10 s + 100 ns per ray and bound of its samples (2 x max layers + refine steps + 8), some 25
// times what the slowest built-in technique needs at one llvmpipe thread; other requests 600 s.
// A worker that crashes, exits, does not answer in time or compiles or draws past its bound is
// killed (the call throws one line: an InputError naming a brought-in shader when the worker died
// or ran past a bound while compiling or drawing it) and the next prepare starts a new one.
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
  // The runner of `threads` llvmpipe threads (<= 0: all cores), its worker started on the first
  // call for that count and kept until the process exits. Throws std::runtime_error when the
  // worker cannot be started or creates no context. A runner serves one caller at a time.
  static GlslRunner& instance(int threads);

  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }
  int threads() const { return threads_; }

  // Uploads the depth map and the rays and builds the program (the technique's, or the
  // brought-in shader's when shader_path is not empty). Throws InputError for compile errors,
  // with the brought-in file's line numbers. A depth map or rays identical to the last ones sent
  // to this runner's worker are not sent again, and the worker keeps its last 64 programs.
  void prepare(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
               const std::string& shader_path = "");

  // One draw over every ray, finished (glFinish); returns its seconds as timed in the worker,
  // without the round trip. The first draw after prepare() may also JIT-compile the shader:
  // time the ones after it.
  double draw();

  // Reads the hits of the last draw back, in batch order (samples: -1 cast for unknown). Throws
  // InputError when a brought-in shader left rays without a hit (it called discard).
  void read(HitBuffers& hits, bool& samples_known) const;

  GlslRunner(const GlslRunner&) = delete;
  GlslRunner& operator=(const GlslRunner&) = delete;
  ~GlslRunner();

 private:
  explicit GlslRunner(int threads);
  struct Worker;
  std::unique_ptr<Worker> worker_;
  std::string renderer_, version_;
  int threads_;
};

}  // namespace heightmarch
