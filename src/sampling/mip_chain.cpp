#include "heightmarch/mip_chain.hpp"

#include <algorithm>
#include <string>

#include "heightmarch/memory_budget.hpp"

namespace heightmarch {

int mip_level_count(int width, int height) {
  int levels = 1;
  for (int side = std::max(width, height); side > 1; side >>= 1) ++levels;
  return levels;
}

std::vector<DepthMap> build_mip_chain(const DepthMap& map) {
  // Levels 1 and up hold a third of level 0 at most.
  check_memory_budget(
      4.0 * (1.0 + 1.0 / 3.0) * double(map.texels.size()),
      "the mip chain of a " + std::to_string(map.width) + "x" + std::to_string(map.height) + " depth map");
  const int levels = mip_level_count(map.width, map.height);
  std::vector<DepthMap> chain;
  chain.reserve(std::size_t(levels));
  chain.push_back(map);
  for (int level = 1; level < levels; ++level) {
    const DepthMap& above = chain.back();
    DepthMap next{std::max(1, above.width / 2), std::max(1, above.height / 2), {}};
    next.texels.resize(std::size_t(next.width) * std::size_t(next.height));
    for (int j = 0; j < next.height; ++j) {
      const int j0 = std::min(2 * j, above.height - 1), j1 = std::min(2 * j + 1, above.height - 1);
      for (int i = 0; i < next.width; ++i) {
        const int i0 = std::min(2 * i, above.width - 1), i1 = std::min(2 * i + 1, above.width - 1);
        next.texels[std::size_t(j) * std::size_t(next.width) + std::size_t(i)] =
            (((above.at(i0, j0) + above.at(i1, j0)) + above.at(i0, j1)) + above.at(i1, j1)) * 0.25f;
      }
    }
    chain.push_back(std::move(next));
  }
  return chain;
}

}  // namespace heightmarch
