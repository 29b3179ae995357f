#pragma once
// The techniques as GLSL (src/glsl/), offscreen, on the same rays and parameters as the CPU
// kernels, in a GL context of one of the GL paths (heightmarch/gl_target.hpp): Mesa's OSMesa
// (llvmpipe), or EGL's device platform (Mesa's software device, llvmpipe again, or a GPU's own
// driver). The GL context lives in a worker process, heightmarch-glsl-worker
// (src/glsl/worker_main.cpp), so only GLSL runs load the GL libraries and libLLVM, and each GL
// target and llvmpipe thread count (read once per process) gets its own context.
//
// The worker is found next to the running executable, or at $HEIGHTMARCH_GLSL_WORKER. It runs
// under an OS memory limit derived from the memory budget (memory_budget.hpp), checks every
// message it is sent (src/glsl/protocol.hpp), and dies with its client: a parent-death signal
// (when started from the process's main thread; the parent of a worker is the thread that
// started it), and its own watch of the channel for the client's hang-up.
// Every wait on it has its step's own bound: start-up (loading the libraries, making the
// context) 20 s; a program's compile and link 20 s; the uploads (sending the request, the
// textures, the precomputed ones) 10 s + 20 ns per byte sent + 1 us per texel of the depth map; a draw
// 10 s + 100 ns per ray and bound of its samples (2 x max layers + refine steps + 8), some 25
// times what the slowest built-in technique needs at one llvmpipe thread; the read-back 10 s +
// 200 ns per ray. A worker that crashes, exits, does not answer in time or compiles or draws past its bound
// is killed (the call throws one line: an InputError naming a brought-in shader when the worker died or ran
// past a bound while compiling or drawing it) and the next prepare starts a new one.
//
// Brought-in shaders (--shader FILE): the file defines LearnOpenGL's
//   vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
// and may use the harness's uniforms `sampler2D depthMap`, `float heightScale` (also spelled
// `height_scale`, the tutorial's name), `float numLayers`, `float minLayers`, `float maxLayers`
// (numLayers = maxLayers, from --layers). Lines of the file that declare these uniforms, and a
// #version line, are dropped so a tutorial's shader pasted as it is compiles. Its depth is the
// depth map at the returned uv; its sample count is unknown.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "heightmarch/gl_target.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

// The GL paths heightmarch-glsl-worker was built with, in the list's order (asked of it once).
std::vector<GlPath> gl_paths_built();
// The target with its path resolved: one given, else OSMesa where the worker has it, else EGL.
// InputError for a path the worker was built without, or a device the target cannot have.
GlTarget resolved(const GlTarget& target);
// EGL's devices as the worker finds them, each with its context's renderer (or why it made none).
std::vector<GlDevice> list_gl_devices();

class GlslRunner {
 public:
  // The runner of a GL target (resolved()) at `threads` llvmpipe threads (<= 0: all cores), its
  // worker started on the first call for that pair and kept until the process exits. Throws
  // std::runtime_error when the worker cannot be started or creates no context, InputError for a
  // target it cannot draw in. A runner serves one caller at a time.
  static GlslRunner& instance(int threads, const GlTarget& target = {});

  // What the worker's context is: path, device, GL_RENDERER, GL_VERSION, GL_VENDOR.
  const GlRenderer& renderer() const { return renderer_; }
  int threads() const { return threads_; }

  // Uploads the depth map and the rays and builds the program (the technique's, or the
  // brought-in shader's when shader_path is not empty). Throws InputError for compile errors,
  // with the brought-in file's line numbers. A depth map or rays identical to the last ones sent
  // to this runner's worker are not sent again, and the worker keeps its last 64 programs.
  void prepare(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
               const std::string& shader_path = "");

  // One draw over every ray, finished (glFinish); its time as timed in the worker, without the
  // round trip. The first draw after prepare() may also JIT-compile the shader: time the ones
  // after it.
  GlDrawTime draw();

  // Reads the hits of the last draw back, in batch order (samples: -1 cast for unknown). Throws
  // InputError when a brought-in shader left rays without a hit (it called discard).
  void read(HitBuffers& hits, bool& samples_known) const;

  GlslRunner(const GlslRunner&) = delete;
  GlslRunner& operator=(const GlslRunner&) = delete;
  ~GlslRunner();

 private:
  GlslRunner(int threads, const GlTarget& target);
  struct Worker;
  std::unique_ptr<Worker> worker_;
  GlRenderer renderer_;
  int threads_;
};

}  // namespace heightmarch
