#pragma once
// The GL side of GlslRunner, in heightmarch-glsl-worker only (heightmarch_gl, the one target that
// links OSMesa): one GL 3.3 core context in llvmpipe. See heightmarch/glsl_runner.hpp for the
// brought-in shaders' contract.
#include <memory>
#include <string>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

class OsmesaRunner {
 public:
  // llvmpipe reads LP_NUM_THREADS once, when the process's first context is created: make one
  // OsmesaRunner per process.
  explicit OsmesaRunner(int threads);
  ~OsmesaRunner();
  OsmesaRunner(const OsmesaRunner&) = delete;
  OsmesaRunner& operator=(const OsmesaRunner&) = delete;

  const std::string& renderer() const { return renderer_; }
  const std::string& version() const { return version_; }

  // The depth map and the rays stay in the context until replaced, so a prepare on the same scene
  // uploads neither again; rays need only tx, ty, vx, vy, vz.
  void set_depth_map(const DepthMap& map);
  void set_rays(const RayBatch& rays);
  // The program of the technique, or of the brought-in shader when shader_path is not empty,
  // compiled and linked (or taken from the last 64 kept); InputError for a brought-in shader's
  // errors. Needs no depth map nor rays, so it runs under its own deadline.
  void compile(const TechniqueParams& params, const std::string& shader_path);
  // The rest of GlslRunner's prepare for the program last compiled, on the depth map and rays last
  // set (both must have been): uniforms, wrap mode, precomputed textures.
  void prepare(const TechniqueParams& params);
  // Fills the hits with a NaN sentinel, which read() finds where a fragment was discarded.
  void clear_hits();
  void draw();
  void read(HitBuffers& hits, bool& samples_known) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  std::string renderer_, version_;
};

}  // namespace heightmarch
