#include "baselines/structured_pom.hpp"

#include "baselines/highway_port.hpp"
#include "baselines/naive_port.hpp"
#include "heightmarch/error.hpp"

namespace heightmarch {

#ifndef HEIGHTMARCH_HAVE_HIGHWAY
// Built without Google Highway (libhwy-dev): it runs nowhere.
TraceRangeFn highway_structured_kernel(Isa) { return nullptr; }
#endif

bool highway_structured_runs(Isa isa) { return highway_structured_kernel(isa) != nullptr; }

HighwayStructuredPom::HighwayStructuredPom(const DepthMap& map, const TechniqueParams& params, Isa isa)
    : params_(params), kernel_(highway_structured_kernel(isa)), texture_(map, params.wrap) {
  if (!kernel_)
    throw InputError("the structured Highway POM does not run at ISA " + to_string(isa) +
                     " in this build on this CPU");
  if (params.technique != Technique::pom ||
      addressing_of(map.width, map.height, params.wrap) != Addressing::repeat_pow2)
    throw InputError("the structured Highway POM runs pom on REPEAT depth maps of power-of-two sides only");
}

void HighwayStructuredPom::run(const RayBatch& rays, HitBuffers& hits) const {
  const KernelTexture texture{texture_.texels.data(), texture_.width, texture_.height, texture_.stride,
                              texture_.wrap};
  trace_tiles(kernel_, texture,
              KernelParams{params_.layers.min_layers,
                           params_.layers.max_layers,
                           0,
                           params_.scale,
                           params_.discard,
                           {params_.light[0], params_.light[1], params_.light[2]}},
              rays, hits);
}

}  // namespace heightmarch
