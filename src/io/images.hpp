#pragma once
// Images for people and data files: PNG, WebP and EXR through OpenImageIO, the uv error heat map,
// the cost map and the colour difference map (the shaded render itself: shading.hpp).
#include <cstdint>
#include <string>
#include <vector>

namespace heightmarch {

// How an image for people is kept: PNG, lossless (trace's outputs), or WebP at quality 80, about a
// fifth of PNG's bytes and the same to the eye (a run's gallery, within its budget:
// docs/measurements.md).
enum class ImageFormat { png, webp };
const char* extension(ImageFormat format);  // ".png", ".webp"

// Both write to a temporary file beside path and rename it into place; throw std::runtime_error.
// write_rgb8 keeps the image in the format its path's extension names.
void write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);
void write_exr(const std::string& path, int width, int height, const std::vector<std::string>& channel_names,
               const std::vector<float>& interleaved);

// The heat map's fixed scale: log10 of the uv error in texels, from 0.01 to 10 texels.
inline constexpr double kHeatMapMinTexels = 0.01;
inline constexpr double kHeatMapMaxTexels = 10.0;

// Per-pixel uv error (texels) as RGB (inferno colours on the fixed scale; grey where a pixel has
// no ray), with a legend strip below: the colour bar and its ticks. out_height includes it.
std::vector<std::uint8_t> error_heat_map(const std::vector<float>& error_texels,
                                         const std::vector<std::uint8_t>& has_ray, int width, int height,
                                         int& out_height);

// The cost map's fixed scale: log2 of the samples a pixel's ray took, from 1 to this many (more
// are drawn as this many), the same for every cost map.
inline constexpr std::uint32_t kCostMapMaxSamples = 1024;

// Per-pixel cost, the samples a pixel's ray took (exact: texel cells solved), as RGB (viridis on
// the fixed log scale; grey where a pixel has no ray), with the same legend strip as the heat
// map: ticks at 1, 4, 16, ..., 1024 and `unit` ("samples", "cells") after the bar.
std::vector<std::uint8_t> cost_map(const std::vector<std::uint32_t>& samples,
                                   const std::vector<std::uint8_t>& has_ray, int width, int height,
                                   const std::string& unit, int& out_height);

// The colour difference map's fixed scale: CIEDE2000 from 0 to this (more is drawn as this).
inline constexpr double kDeltaEMapMax = 10.0;

// Per-pixel colour difference (CIEDE2000, colour_difference.hpp) as RGB (cividis on the fixed
// linear scale; grey where a pixel has no ray), with the legend strip: ticks at 0, 1, 2 (seen at a
// glance above it), 5 and 10.
std::vector<std::uint8_t> colour_difference_map(const std::vector<float>& delta_e,
                                                const std::vector<std::uint8_t>& has_ray, int width,
                                                int height, int& out_height);

}  // namespace heightmarch
