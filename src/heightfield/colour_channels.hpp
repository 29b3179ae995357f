#pragma once
// A colour image file read as three channels (an albedo: the colour texture a map is shaded with,
// src/io/shading.hpp), with the checks and the memory budget of a depth map file.
#include <array>
#include <string>

#include "heightmarch/heightfield.hpp"

namespace heightmarch {

struct ColourChannels {
  // R, G and B, each normalised as a depth map is (OIIO's normalisation of integer formats); a
  // grey image (one or two channels) gives its first channel three times. Alpha is never read.
  std::array<DepthMap, 3> rgb;
  // Whether the values are sRGB-encoded: the file says so (OIIO's oiio:ColorSpace), or says
  // nothing and stores integers (PNG, JPEG, 8- and 16-bit TIFF); a float file (EXR, PFM, HDR) is
  // linear unless it says sRGB.
  bool srgb = true;
};

// Throws InputError for what load_depth_map refuses (special or unreadable files, absurd sizes,
// truncated pixel data) and for NaN or infinite values; values outside [0, 1] are clamped.
ColourChannels load_colour_channels(const std::string& path);

// A colour texture's path as given (--albedo, a map list's :albedo=), once it names something
// that exists; else InputError naming `what`.
std::string checked_albedo_path(const std::string& path, const std::string& what);

}  // namespace heightmarch
