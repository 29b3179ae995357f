#include "heightmarch/precomputed.hpp"

#include <chrono>

namespace heightmarch {

PrecomputedTextures build_precomputed(const DepthMap& map, Wrap wrap, Needs needs) {
  PrecomputedTextures textures;
  if (has(needs, Needs::min_depth_pyramid)) {
    const auto start = std::chrono::steady_clock::now();
    textures.pyramid = std::make_shared<const MinDepthPyramid>(map, wrap);
    textures.build_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (has(needs, Needs::cone_map)) {
    textures.cone_map = cached_cone_map(map, wrap);
    textures.build_seconds += textures.cone_map->build_seconds;
  }
  return textures;
}

}  // namespace heightmarch
