// heightmarch::glsl: POM-32 as GLSL in the worker process over the builtin `flat` heightfield.
#include <cstdlib>
#include <exception>
#include <heightmarch/glsl_runner.hpp>

#include "flat_rays.hpp"

int main() try {
  using namespace heightmarch;
  // The worker is not beside this executable: tell GlslRunner where the package put it.
  setenv("HEIGHTMARCH_GLSL_WORKER", HEIGHTMARCH_GLSL_WORKER_PATH, 0);
  const DepthMap map = make_builtin_heightfield("flat", 64, 1);
  TechniqueParams params;
  validate(params);
  const RayBatch rays = flat_rays();
  GlslRunner& runner = GlslRunner::instance(1);
  runner.prepare(map, params, rays);
  runner.draw();
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  return check_flat_hits("pom 32 glsl", rays, hits, params.scale);
} catch (const std::exception& e) {
  std::fprintf(stderr, "glsl_flat: %s\n", e.what());
  return 1;
}
