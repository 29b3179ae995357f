#include "heightmarch/precomputed.hpp"

#include <chrono>

namespace heightmarch {

std::shared_ptr<const MinDepthPyramid> build_min_depth_pyramid(const DepthMap& map, Wrap wrap) {
  const auto start = std::chrono::steady_clock::now();
  auto pyramid = std::make_shared<MinDepthPyramid>(map, wrap);
  pyramid->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return pyramid;
}

PrecomputedTextures build_precomputed(const DepthMap& map, Wrap wrap, Needs needs) {
  PrecomputedTextures textures;
#define HEIGHTMARCH_BUILD_PRECOMPUTED(id, type, builder, ...) \
  if (has(needs, Needs::id)) {                                \
    textures.id = builder(map, wrap);                         \
    textures.build_seconds += textures.id->build_seconds;     \
  }
  HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_BUILD_PRECOMPUTED)
#undef HEIGHTMARCH_BUILD_PRECOMPUTED
  return textures;
}

}  // namespace heightmarch
