#pragma once
// Depth maps (SPEC section 1): W x H floats in [0, 1], 0 = top plane, 1 = deepest. Row 0 is v = 0.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace heightmarch {

struct DepthMap {
  int width = 0;
  int height = 0;
  std::vector<float> texels;  // row-major, texels[j * width + i]

  float at(int i, int j) const { return texels[std::size_t(j) * std::size_t(width) + std::size_t(i)]; }
};

enum class Convention { depth, height };  // height: white = high, turned into depth as 1 - h

// Largest accepted side of a depth map, loaded or built in.
inline constexpr int kMaxDepthMapSide = 16384;

// Loads any image OpenImageIO reads; the first channel is the depth. Throws InputError on
// unreadable files, absurd sizes and NaN/Inf texels; values outside [0, 1] are clamped with a
// warning on stderr.
DepthMap load_depth_map(const std::string& path, Convention convention);

// Procedural heightfields, deterministic for a given resolution and seed.
const std::vector<std::string>& builtin_heightfield_names();
DepthMap make_builtin_heightfield(const std::string& name, int resolution, std::uint64_t seed);

// "builtin:NAME" or a file path.
DepthMap load_heightfield(const std::string& spec, int resolution, std::uint64_t seed,
                          Convention convention);

}  // namespace heightmarch
