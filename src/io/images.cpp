#include "io/images.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace heightmarch {
namespace {

// The encoder writes through the atomic writer's temporary (OIIO's IOFile over its descriptor), so
// it never opens a path itself; OIIO chooses it by the final name's extension.
void write_image(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                 const void* pixels) {
  AtomicFile file(path);
  const int fd = ::dup(file.descriptor());
  std::FILE* stream = fd >= 0 ? ::fdopen(fd, "wb") : nullptr;
  if (!stream) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw std::runtime_error(path + ": cannot write (" + std::strerror(error) + ")");
  }
  std::string why;
  {
    OIIO::Filesystem::IOFile proxy(stream, OIIO::Filesystem::IOProxy::Write);
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->set_ioproxy(&proxy) || !out->open(path, spec) || !out->write_image(type, pixels) ||
        !out->close())
      why = out ? out->geterror() : OIIO::geterror();
  }
  const bool write_failed = std::ferror(stream) != 0;
  const int error = errno;
  if (std::fclose(stream) != 0 && why.empty()) why = std::strerror(errno);
  if (write_failed && why.empty()) why = std::strerror(error);
  if (!why.empty()) {
    for (char& c : why)
      if (c == '\n') c = ' ';
    throw std::runtime_error(path + ": cannot write (" + why + ")");  // the temporary goes with `file`
  }
  file.commit();
}

using Colour = std::array<std::uint8_t, 3>;
using Palette = std::array<std::array<float, 3>, 9>;  // 9 anchors from dark to bright

// matplotlib's inferno (the error map) and viridis (the cost map): perceptually uniform, and
// distinct, so the two maps are not read for each other.
constexpr Palette kInferno = {{{0, 0, 4},
                               {31, 12, 72},
                               {85, 15, 109},
                               {136, 34, 106},
                               {186, 54, 85},
                               {227, 89, 51},
                               {249, 140, 10},
                               {249, 201, 50},
                               {252, 255, 164}}};
constexpr Palette kViridis = {{{68, 1, 84},
                               {71, 44, 122},
                               {59, 81, 139},
                               {44, 113, 142},
                               {33, 144, 141},
                               {39, 173, 129},
                               {92, 200, 99},
                               {170, 220, 50},
                               {253, 231, 37}}};
// matplotlib's cividis (the colour difference map): neither of the two above.
constexpr Palette kCividis = {{{0, 34, 78},
                               {18, 53, 112},
                               {59, 73, 108},
                               {87, 92, 109},
                               {112, 113, 115},
                               {138, 134, 120},
                               {166, 157, 117},
                               {196, 181, 105},
                               {254, 232, 56}}};
constexpr Colour kNoRay = {96, 96, 96};

Colour colour_at(const Palette& palette, double t) {
  t = std::clamp(t, 0.0, 1.0) * double(palette.size() - 1);
  const std::size_t i = std::min<std::size_t>(std::size_t(t), palette.size() - 2);
  const double f = t - double(i);
  Colour c;
  for (int k = 0; k < 3; ++k)
    c[k] = std::uint8_t(std::lround(palette[i][k] + f * (palette[i + 1][k] - palette[i][k])));
  return c;
}

double heat_position(double texels) {
  const double lo = std::log10(kHeatMapMinTexels), hi = std::log10(kHeatMapMaxTexels);
  return (std::log10(std::max(texels, kHeatMapMinTexels)) - lo) / (hi - lo);
}

// A 3x5 bitmap font for the legends: digits, '.', and the letters of "texels", "samples",
// "cells" and "dE00".
const char* glyph(char c) {
  switch (c) {
    case '0':
      return "111101101101111";
    case '1':
      return "010110010010111";
    case '2':
      return "111001111100111";
    case '3':
      return "111001111001111";
    case '4':
      return "101101111001001";
    case '5':
      return "111100111001111";
    case '6':
      return "111100111101111";
    case '7':
      return "111001001001001";
    case '8':
      return "111101111101111";
    case '9':
      return "111101111001111";
    case '.':
      return "000000000000010";
    case 'a':
      return "000110011101111";
    case 'c':
      return "000011100100011";
    case 'd':
      return "001001011101011";
    case 'E':
      return "111100110100111";
    case 'e':
      return "000111111100111";
    case 'l':
      return "110010010010111";
    case 'm':
      return "000111111101101";
    case 'p':
      return "000110101110100";
    case 's':
      return "000011110001110";
    case 't':
      return "010111010010011";
    case 'x':
      return "000101010010101";
    default:
      return "000000000000000";
  }
}

void draw_text(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y, int scale,
               const std::string& text) {
  for (char c : text) {
    const char* g = glyph(c);
    for (int gy = 0; gy < 5; ++gy)
      for (int gx = 0; gx < 3; ++gx)
        if (g[gy * 3 + gx] == '1')
          for (int sy = 0; sy < scale; ++sy)
            for (int sx = 0; sx < scale; ++sx) {
              const int px = x + gx * scale + sx, py = y + gy * scale + sy;
              if (px < 0 || py < 0 || px >= width || py >= height) continue;
              std::uint8_t* p = &rgb[3 * (std::size_t(py) * width + px)];
              p[0] = p[1] = p[2] = 235;
            }
    x += 4 * scale;
  }
}

struct LegendTick {
  double position;  // along the bar, [0, 1]
  std::string label;
};

// The legend's size step (text 5 px high per step) and the strip's height, for an image's width.
int legend_scale(int width) { return std::clamp(width / 256, 1, 4); }
int legend_height(int width) { return 14 * legend_scale(width); }

// A map of `height` rows with the legend strip below them: dark, then the palette as a colour
// bar over 70% of the width, a tick and label under each tick position, the unit after the bar.
std::vector<std::uint8_t> image_with_legend(int width, int height, const Palette& palette,
                                            const std::vector<LegendTick>& ticks, const std::string& unit,
                                            const std::function<Colour(std::size_t pixel)>& pixel_colour,
                                            int& out_height) {
  const int scale = legend_scale(width);
  out_height = height + legend_height(width);
  std::vector<std::uint8_t> rgb(3 * std::size_t(width) * std::size_t(out_height), 24);
  for (std::size_t p = 0; p < std::size_t(width) * std::size_t(height); ++p) {
    const Colour c = pixel_colour(p);
    std::copy(c.begin(), c.end(), &rgb[3 * p]);
  }
  const int bar_x0 = width / 20, bar_x1 = bar_x0 + width * 7 / 10, bar_y = height + scale, bar_h = 3 * scale;
  for (int x = bar_x0; x < bar_x1; ++x) {
    const Colour c = colour_at(palette, double(x - bar_x0) / double(std::max(1, bar_x1 - bar_x0 - 1)));
    for (int y = bar_y; y < bar_y + bar_h; ++y)
      std::copy(c.begin(), c.end(), &rgb[3 * (std::size_t(y) * width + x)]);
  }
  for (const LegendTick& tick : ticks) {
    const int x = bar_x0 + int(std::lround((bar_x1 - 1 - bar_x0) * tick.position));
    if (x < 0 || x >= width) continue;
    for (int y = bar_y + bar_h; y < bar_y + bar_h + scale; ++y) {
      std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
      p[0] = p[1] = p[2] = 235;
    }
    const int text_width = int(tick.label.size()) * 4 * scale;
    draw_text(rgb, width, out_height, std::clamp(x - text_width / 2, 0, std::max(0, width - text_width)),
              bar_y + bar_h + 2 * scale, scale, tick.label);
  }
  draw_text(rgb, width, out_height, bar_x1 + 8 * scale, bar_y + 2 * scale, scale, unit);
  return rgb;
}

}  // namespace

const char* extension(ImageFormat format) { return format == ImageFormat::webp ? ".webp" : ".png"; }

void write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".webp") == 0)
    spec.attribute("compression", "webp:80");
  write_image(path, spec, OIIO::TypeDesc::UINT8, rgb.data());
}

void write_exr(const std::string& path, int width, int height, const std::vector<std::string>& channel_names,
               const std::vector<float>& interleaved) {
  OIIO::ImageSpec spec(width, height, int(channel_names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channel_names;
  spec.alpha_channel = -1;
  write_image(path, spec, OIIO::TypeDesc::FLOAT, interleaved.data());
}

std::vector<std::uint8_t> error_heat_map(const std::vector<float>& error_texels,
                                         const std::vector<std::uint8_t>& has_ray, int width, int height,
                                         int& out_height) {
  // A tick at each decade of the fixed scale.
  const std::vector<LegendTick> ticks = {{0.0, "0.01"}, {1.0 / 3.0, "0.1"}, {2.0 / 3.0, "1"}, {1.0, "10"}};
  return image_with_legend(
      width, height, kInferno, ticks, "texels",
      [&](std::size_t p) {
        return has_ray[p] ? colour_at(kInferno, heat_position(error_texels[p])) : kNoRay;
      },
      out_height);
}

std::vector<std::uint8_t> cost_map(const std::vector<std::uint32_t>& samples,
                                   const std::vector<std::uint8_t>& has_ray, int width, int height,
                                   const std::string& unit, int& out_height) {
  // One log2 scale for every cost map, 1 to kCostMapMaxSamples: maps side by side (the gallery's
  // column, a report's images) compare by colour. A tick every factor of 4.
  const double top = std::log2(double(kCostMapMaxSamples));
  std::vector<LegendTick> ticks;
  for (std::uint32_t v = 1; v <= kCostMapMaxSamples; v *= 4)
    ticks.push_back({std::log2(double(v)) / top, std::to_string(v)});
  return image_with_legend(
      width, height, kViridis, ticks, unit,
      [&](std::size_t p) {
        const double n = std::clamp(double(samples[p]), 1.0, double(kCostMapMaxSamples));
        return has_ray[p] ? colour_at(kViridis, std::log2(n) / top) : kNoRay;
      },
      out_height);
}

std::vector<std::uint8_t> colour_difference_map(const std::vector<float>& delta_e,
                                                const std::vector<std::uint8_t>& has_ray, int width,
                                                int height, int& out_height) {
  const std::vector<LegendTick> ticks = {{0.0, "0"},
                                         {1.0 / kDeltaEMapMax, "1"},
                                         {2.0 / kDeltaEMapMax, "2"},
                                         {5.0 / kDeltaEMapMax, "5"},
                                         {1.0, "10"}};
  return image_with_legend(
      width, height, kCividis, ticks, "dE00",
      [&](std::size_t p) { return has_ray[p] ? colour_at(kCividis, delta_e[p] / kDeltaEMapMax) : kNoRay; },
      out_height);
}

}  // namespace heightmarch
