// The check of a depth map handed over whole, apart from the image loader (load.cpp) so the GLSL
// worker, which checks every map it is sent, links no OpenImageIO.
#include <cmath>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"

namespace heightmarch {

void check_depth_map(const DepthMap& map, const std::string& what) {
  if (map.width < 1 || map.height < 1 || map.width > kMaxDepthMapSide || map.height > kMaxDepthMapSide)
    throw InputError(what + ": a depth map of " + std::to_string(map.width) + "x" +
                     std::to_string(map.height) + " texels (sides from 1 to " +
                     std::to_string(kMaxDepthMapSide) + ")");
  if (map.texels.size() != std::size_t(map.width) * std::size_t(map.height))
    throw InputError(what + ": " + std::to_string(map.texels.size()) + " texels for a depth map of " +
                     std::to_string(map.width) + "x" + std::to_string(map.height));
  std::size_t not_finite = 0, outside = 0, first_not_finite = 0, first_outside = 0;
  for (std::size_t k = 0; k < map.texels.size(); ++k) {
    const float d = map.texels[k];
    if (!std::isfinite(d)) {
      if (not_finite++ == 0) first_not_finite = k;
    } else if (d < 0.0f || d > 1.0f) {
      if (outside++ == 0) first_outside = k;
    }
  }
  const auto at = [&](std::size_t k) {
    return " (first at " + std::to_string(k % std::size_t(map.width)) + "," +
           std::to_string(k / std::size_t(map.width)) + ")";
  };
  if (not_finite)
    throw InputError(what + ": " + std::to_string(not_finite) + " NaN/Inf texels" + at(first_not_finite));
  if (outside)
    throw InputError(what + ": " + std::to_string(outside) + " texels outside [0, 1]" + at(first_outside));
}

}  // namespace heightmarch
