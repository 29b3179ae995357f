#include "io/images.hpp"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace heightmarch {
namespace {

// OIIO chooses the writer by extension, so the temporary keeps it: "x.png" -> "x.tmp-PID.png".
void write_image(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc type, const void* pixels) {
  const std::filesystem::path final_path(path);
  const std::string temporary = (final_path.parent_path() / (final_path.stem().string() + ".tmp-" +
                                                               std::to_string(::getpid()) + final_path.extension().string()))
                                    .string();
  auto out = OIIO::ImageOutput::create(temporary);
  if (!out || !out->open(temporary, spec) || !out->write_image(type, pixels) || !out->close()) {
    std::string why = out ? out->geterror() : OIIO::geterror();
    for (char& c : why)
      if (c == '\n') c = ' ';
    out.reset();  // closes the file before it is removed
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(path + ": cannot write (" + why + ")");
  }
  out.reset();
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    const std::string why = ec.message();
    std::filesystem::remove(temporary, ec);
    throw std::runtime_error(path + ": cannot write (" + why + ")");
  }
}

// Inferno, 9 anchors from dark to bright.
constexpr std::array<std::array<float, 3>, 9> kInferno = {{{0, 0, 4},       {31, 12, 72},   {85, 15, 109},
                                                           {136, 34, 106},  {186, 54, 85},  {227, 89, 51},
                                                           {249, 140, 10},  {249, 201, 50}, {252, 255, 164}}};

std::array<std::uint8_t, 3> inferno(double t) {
  t = std::clamp(t, 0.0, 1.0) * double(kInferno.size() - 1);
  const std::size_t i = std::min<std::size_t>(std::size_t(t), kInferno.size() - 2);
  const double f = t - double(i);
  std::array<std::uint8_t, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = std::uint8_t(std::lround(kInferno[i][k] + f * (kInferno[i + 1][k] - kInferno[i][k])));
  return c;
}

double heat_position(double texels) {
  const double lo = std::log10(kHeatMapMinTexels), hi = std::log10(kHeatMapMaxTexels);
  return (std::log10(std::max(texels, kHeatMapMinTexels)) - lo) / (hi - lo);
}

// A 3x5 bitmap font for the legend: digits, '.', and the letters of "texels".
const char* glyph(char c) {
  switch (c) {
    case '0': return "111101101101111";
    case '1': return "010110010010111";
    case '.': return "000000000000010";
    case 't': return "010111010010011";
    case 'e': return "000111111100111";
    case 'x': return "000101010010101";
    case 'l': return "110010010010111";
    case 's': return "000011110001110";
    default: return "000000000000000";
  }
}

void draw_text(std::vector<std::uint8_t>& rgb, int width, int height, int x, int y, int scale, const std::string& text) {
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

}  // namespace

void write_png_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  write_image(path, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, rgb.data());
}

void write_exr(const std::string& path, int width, int height, const std::vector<std::string>& channel_names,
               const std::vector<float>& interleaved) {
  OIIO::ImageSpec spec(width, height, int(channel_names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = channel_names;
  spec.alpha_channel = -1;
  write_image(path, spec, OIIO::TypeDesc::FLOAT, interleaved.data());
}

std::vector<std::uint8_t> error_heat_map(const std::vector<float>& error_texels, const std::vector<std::uint8_t>& has_ray,
                                         int width, int height, int& out_height) {
  const int scale = std::clamp(width / 256, 1, 4);  // legend text 5 px high per scale step
  const int legend = 14 * scale;
  out_height = height + legend;
  std::vector<std::uint8_t> rgb(3 * std::size_t(width) * std::size_t(out_height), 24);
  for (std::size_t p = 0; p < std::size_t(width) * std::size_t(height); ++p) {
    const auto c = has_ray[p] ? inferno(heat_position(error_texels[p])) : std::array<std::uint8_t, 3>{96, 96, 96};
    std::copy(c.begin(), c.end(), &rgb[3 * p]);
  }
  // Colour bar over 70% of the width, ticks and labels at each decade, "texels" after it.
  const int bar_x0 = width / 20, bar_x1 = bar_x0 + width * 7 / 10, bar_y = height + scale, bar_h = 3 * scale;
  for (int x = bar_x0; x < bar_x1; ++x) {
    const auto c = inferno(double(x - bar_x0) / double(std::max(1, bar_x1 - bar_x0 - 1)));
    for (int y = bar_y; y < bar_y + bar_h; ++y) std::copy(c.begin(), c.end(), &rgb[3 * (std::size_t(y) * width + x)]);
  }
  const char* labels[] = {"0.01", "0.1", "1", "10"};
  for (int k = 0; k < 4; ++k) {
    const int x = bar_x0 + (bar_x1 - 1 - bar_x0) * k / 3;
    for (int y = bar_y + bar_h; y < bar_y + bar_h + scale; ++y) {
      std::uint8_t* p = &rgb[3 * (std::size_t(y) * width + x)];
      p[0] = p[1] = p[2] = 235;
    }
    const int text_width = int(std::string(labels[k]).size()) * 4 * scale;
    draw_text(rgb, width, out_height, std::clamp(x - text_width / 2, 0, width - text_width), bar_y + bar_h + 2 * scale,
              scale, labels[k]);
  }
  draw_text(rgb, width, out_height, bar_x1 + 8 * scale, bar_y + 2 * scale, scale, "texels");
  return rgb;
}

std::vector<std::uint8_t> shade_render(const DepthMap& map, Wrap wrap, float scale, const std::vector<float>& u,
                                       const std::vector<float>& v, const std::vector<float>& shadow,
                                       const std::vector<std::uint8_t>& has_ray, int width, int height,
                                       const float light[3]) {
  std::vector<std::uint8_t> rgb(3 * std::size_t(width) * std::size_t(height), 16);
  const float du = 1.0f / float(map.width), dv = 1.0f / float(map.height);
  for (std::size_t p = 0; p < std::size_t(width) * std::size_t(height); ++p) {
    if (!has_ray[p]) continue;
    // Surface height is -depth * scale; its slopes per uv give the normal.
    const float sx = (sample_depth(map, wrap, u[p] + du, v[p]) - sample_depth(map, wrap, u[p] - du, v[p])) / (2 * du);
    const float sy = (sample_depth(map, wrap, u[p], v[p] + dv) - sample_depth(map, wrap, u[p], v[p] - dv)) / (2 * dv);
    float n[3] = {sx * scale, sy * scale, 1.0f};
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const float diffuse = std::max(0.0f, (n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / len);
    // Warm base with a grid every 1/8 in uv, slightly darker deeper down.
    const float gu = u[p] * 8 - std::floor(u[p] * 8), gv = v[p] * 8 - std::floor(v[p] * 8);
    const bool line = gu < 0.03f || gv < 0.03f;
    const float depth = sample_depth(map, wrap, u[p], v[p]);
    const float tint = 1.0f - 0.35f * depth;
    const float base[3] = {line ? 0.25f : 0.85f * tint, line ? 0.25f : 0.62f * tint, line ? 0.3f : 0.45f * tint};
    const float s = shadow[p] * shadow[p] * shadow[p] * shadow[p];
    const float light_amount = 0.25f + 0.75f * diffuse * s;
    for (int k = 0; k < 3; ++k)
      rgb[3 * p + k] = std::uint8_t(std::clamp(std::lround(255.0f * base[k] * light_amount), 0L, 255L));
  }
  return rgb;
}

}  // namespace heightmarch
