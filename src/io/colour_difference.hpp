#pragma once
// The difference between two shaded images as a player sees it (docs/measures.md#the-shaded-image):
// CIEDE2000 per pixel (Little CMS's cmsCIE2000DeltaE, kL = kC = kH = 1), each image encoded to
// sRGB and taken to CIELAB under D65, sRGB's white, by Little CMS's sRGB profile. A colour
// difference rather than SSIM: it is a pixel's own, so the share of pixels a player would see
// differ has a threshold in its unit, and a difference image shows where.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "io/shading.hpp"

namespace heightmarch {

// A difference of 2 is seen at a glance (below 1, not seen; 1 to 2, seen on close inspection, on
// the usual reading of the CIEDE2000 scale): the share of pixels above it is what a player sees
// differ while playing.
inline constexpr double kVisibleDeltaE = 2.0;

// Per pixel CIEDE2000 between two images of one size, in parallel over rows.
std::vector<float> ciede2000(const LinearImage& a, const LinearImage& b);

// The difference over the pixels `compared` marks: its mean, nearest-rank 99th percentile, and
// the share of those pixels above kVisibleDeltaE.
struct ImageError {
  std::size_t pixels = 0;
  double mean = 0, p99 = 0, visible_share = 0;
};
ImageError summarize_image_error(const std::vector<float>& delta_e,
                                 const std::vector<std::uint8_t>& compared);

}  // namespace heightmarch
