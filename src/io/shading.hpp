#pragma once
// The shaded image (docs/measures.md#the-shaded-image): a view's hits as a player sees them. Each
// pixel's hit is lit by one directional light (Lambert with an ambient term, times the soft shadow
// factor to the 4th power as the "Parallax Occlusion Mapping in GLSL" tutorial does) on the
// heightfield's colour texture (its albedo) at the hit's uv, with the depth map's normal there;
// in linear light, encoded to sRGB for files and for the colour difference
// (colour_difference.hpp).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/sampler.hpp"

namespace heightmarch {

// An RGB colour texture in linear light, each channel with its mip chain (build_mip_chain), read
// trilinearly at the level of detail of the pixel's footprint, as a shader's texture() reads a
// mipmapped diffuse map.
struct Albedo {
  std::array<std::vector<DepthMap>, 3> chains;
  std::string source;  // "procedural", or the file's path
};

// The colour texture of a map that has none (every builtin): the depth map's texels coloured,
// sand (sRGB 217, 158, 115) at the top plane darkening linearly to 40% of it at the deepest, on a
// checkerboard of 8 x 8 squares over the map (every other square at 70%), so a hit's depth and its
// place on a flat region both show in colour. At the depth map's size.
Albedo procedural_albedo(const DepthMap& map);
// A user's colour texture (--albedo; docs/measures.md#the-shaded-image): its first three channels
// (a grey image's first), sRGB-decoded where encoded (load_colour_channels). Throws InputError.
Albedo load_albedo(const std::string& path);

// sRGB's transfer function and its inverse, on [0, 1].
float srgb_encode(float linear);
float srgb_decode(float encoded);

// What shades a view: the depth map (its level-0 normals), its colour texture, the wrap mode both
// are read with, the height scale and the unit vector towards the light.
struct Shading {
  const DepthMap* map = nullptr;
  const Albedo* albedo = nullptr;
  Wrap wrap = Wrap::repeat;
  float scale = 0.1f;
  std::array<float, 3> light{0.5773503f, 0.5773503f, 0.5773503f};
};

// A picture in linear light: 3 floats (R, G, B) a pixel, row-major.
struct LinearImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

// The colour of a pixel no ray of the view covers (sRGB 16, 16, 16), and of a discarded ray.
inline constexpr float kBackgroundLinear = 0.0052f;
inline constexpr float kAmbient = 0.25f;  // the light's share that reaches every hit

// Linear RGB of one hit at uv (with its shadow factor; 1 without one), the albedo read at the
// footprint (du_dx, dv_dx, du_dy, dv_dy: how the base coordinate moves to the next pixel).
std::array<float, 3> shade(const Shading& shading, float u, float v, float shadow, float du_dx, float dv_dx,
                           float du_dy, float dv_dy);

// Adds `weight` times each pixel's colour to `image` (sized to the view's image, zero, on first
// use): its ray's hit shaded, with the ray's footprint times footprint_scale (1 / n for one of n x
// n subpixel rays), or the background where the pixel has no ray or its ray was discarded. In
// parallel over rows.
void accumulate_shaded(const Shading& shading, const RayBatch& rays, const HitBuffers& hits,
                       float footprint_scale, float weight, LinearImage& image);

// 8-bit sRGB (PNG's), 3 bytes a pixel.
std::vector<std::uint8_t> srgb8(const LinearImage& image);

}  // namespace heightmarch
