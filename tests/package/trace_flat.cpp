// heightmarch::core: POM-32 on the CPU's widest ISA over the builtin `flat` heightfield.
#include <exception>
#include <heightmarch/isa.hpp>
#include <heightmarch/tracer.hpp>

#include "flat_rays.hpp"

int main() try {
  using namespace heightmarch;
  const DepthMap map = make_builtin_heightfield("flat", 64, 1);
  TechniqueParams params;  // POM, 32 layers, s = 0.1, wrap repeat
  validate(params);
  const RayBatch rays = flat_rays();
  const Tracer tracer(map, params, best_isa());
  HitBuffers hits;
  hits.resize(rays.size());
  tracer.run(rays, hits);
  return check_flat_hits(("pom 32 " + to_string(best_isa())).c_str(), rays, hits, params.scale);
} catch (const std::exception& e) {
  std::fprintf(stderr, "trace_flat: %s\n", e.what());
  return 1;
}
