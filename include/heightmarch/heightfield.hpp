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

// Where a depth map comes from: a builtin (with its resolution and seed) or an image file (with
// its convention). Parsed once at the edge (command line, plan) and passed on typed.
struct HeightfieldSource {
  std::string builtin;  // a builtin's name, or empty
  std::string path;     // an image file, when builtin is empty
  int resolution = 512;
  std::uint64_t seed = 1;
  Convention convention = Convention::depth;

  std::string label() const;     // "bricks", or the file name without directories
  std::string describe() const;  // "builtin:bricks", or the path
  friend bool operator==(const HeightfieldSource&, const HeightfieldSource&) = default;
};

// "builtin:NAME", a builtin's bare name (when no such file exists), or a file path. Throws
// InputError for an unknown builtin or a resolution outside [1, kMaxDepthMapSide].
HeightfieldSource parse_heightfield(const std::string& text, int resolution = 512,
                                    std::uint64_t seed = 1, Convention convention = Convention::depth);

DepthMap load_heightfield(const HeightfieldSource& source);

}  // namespace heightmarch
