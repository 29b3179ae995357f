#include "io/shading.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "heightfield/colour_channels.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/mip_chain.hpp"

namespace heightmarch {
namespace {

// What the three chains of an albedo of W x H texels hold: 4/3 of 3 floats a texel.
void check_albedo_budget(int width, int height, const std::string& what) {
  check_memory_budget(16.0 * double(width) * double(height), what);
}

Albedo from_channels(std::array<DepthMap, 3> rgb, std::string source) {
  Albedo albedo;
  for (std::size_t c = 0; c < 3; ++c) albedo.chains[c] = build_mip_chain(rgb[c]);
  albedo.source = std::move(source);
  return albedo;
}

}  // namespace

float srgb_encode(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float encoded) {
  const float x = std::clamp(encoded, 0.0f, 1.0f);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

Albedo procedural_albedo(const DepthMap& map) {
  check_albedo_budget(map.width, map.height,
                      "the procedural colour texture of a " + std::to_string(map.width) + "x" +
                          std::to_string(map.height) + " depth map");
  const float sand[3] = {srgb_decode(217.0f / 255.0f), srgb_decode(158.0f / 255.0f),
                         srgb_decode(115.0f / 255.0f)};
  std::array<DepthMap, 3> rgb;
  for (DepthMap& channel : rgb) channel = {map.width, map.height, std::vector<float>(map.texels.size())};
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      // The square of the 8 x 8 board that holds the texel's centre.
      const int square_u = int(8.0 * (i + 0.5) / map.width), square_v = int(8.0 * (j + 0.5) / map.height);
      const float board = (square_u + square_v) % 2 ? 0.7f : 1.0f;
      const float tint = 1.0f - 0.6f * map.at(i, j);
      for (std::size_t c = 0; c < 3; ++c)
        rgb[c].texels[std::size_t(j) * std::size_t(map.width) + std::size_t(i)] = sand[c] * tint * board;
    }
  return from_channels(std::move(rgb), "procedural");
}

Albedo load_albedo(const std::string& path) {
  ColourChannels colour = load_colour_channels(path);
  check_albedo_budget(colour.rgb[0].width, colour.rgb[0].height, path + " (its colour texture's mip chains)");
  if (colour.srgb)
    for (DepthMap& channel : colour.rgb)
      for (float& t : channel.texels) t = srgb_decode(t);
  return from_channels(std::move(colour.rgb), path);
}

std::array<float, 3> shade(const Shading& s, float u, float v, float shadow, float du_dx, float dv_dx,
                           float du_dy, float dv_dy) {
  const DepthMap& map = *s.map;
  // The surface's height is -depth * scale: its slopes over uv, by central differences of the
  // level-0 bilinear surface one texel apart, give the normal (scale dD/du, scale dD/dv, 1).
  const float du = 1.0f / float(map.width), dv = 1.0f / float(map.height);
  const float sx = (sample_depth(map, s.wrap, u + du, v) - sample_depth(map, s.wrap, u - du, v)) / (2 * du);
  const float sy = (sample_depth(map, s.wrap, u, v + dv) - sample_depth(map, s.wrap, u, v - dv)) / (2 * dv);
  const float n[3] = {sx * s.scale, sy * s.scale, 1.0f};
  const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const float diffuse = std::max(0.0f, (n[0] * s.light[0] + n[1] * s.light[1] + n[2] * s.light[2]) / length);
  const float shadow4 = shadow * shadow * shadow * shadow;
  const float lit = kAmbient + (1.0f - kAmbient) * diffuse * shadow4;
  std::array<float, 3> colour;
  for (std::size_t c = 0; c < 3; ++c) {
    const std::vector<DepthMap>& chain = s.albedo->chains[c];
    const float lod = level_of_detail(du_dx, dv_dx, du_dy, dv_dy, float(chain[0].width),
                                      float(chain[0].height), int(chain.size()) - 1);
    colour[c] = sample_depth(chain, s.wrap, u, v, lod) * lit;
  }
  return colour;
}

void accumulate_shaded(const Shading& s, const RayBatch& rays, const HitBuffers& hits, float footprint_scale,
                       float weight, LinearImage& image) {
  const int w = rays.image_width, h = rays.image_height;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  if (image.rgb.empty()) {
    check_memory_budget(16.0 * double(pixels),
                        "a shaded image of " + std::to_string(w) + "x" + std::to_string(h));
    image = {w, h, std::vector<float>(3 * pixels, 0.0f)};
  }
  std::vector<std::uint32_t> ray_at(pixels, kPaddingRay);
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i) && !hits.discarded[i]) ray_at[rays.origin[i]] = std::uint32_t(i);
  tbb::parallel_for(0, h, [&](int y) {
    for (std::size_t p = std::size_t(y) * std::size_t(w); p < std::size_t(y + 1) * std::size_t(w); ++p) {
      const std::uint32_t i = ray_at[p];
      std::array<float, 3> colour{kBackgroundLinear, kBackgroundLinear, kBackgroundLinear};
      if (i != kPaddingRay)
        colour = shade(s, hits.u[i], hits.v[i], hits.shadow[i], rays.du_dx[i] * footprint_scale,
                       rays.dv_dx[i] * footprint_scale, rays.du_dy[i] * footprint_scale,
                       rays.dv_dy[i] * footprint_scale);
      for (std::size_t c = 0; c < 3; ++c) image.rgb[3 * p + c] += weight * colour[c];
    }
  });
}

std::vector<std::uint8_t> srgb8(const LinearImage& image) {
  std::vector<std::uint8_t> out(image.rgb.size());
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = std::uint8_t(std::lround(255.0f * srgb_encode(image.rgb[k])));
  return out;
}

}  // namespace heightmarch
