// The cost map (samples per pixel) and its legend, shared with the error map: sizes, colours at
// the ends of the scale, the legend's bar and digits; and cost.png written by trace --out.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "io/images.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

using Pixel = std::array<int, 3>;

Pixel pixel(const std::vector<std::uint8_t>& rgb, int width, int x, int y) {
  const std::size_t p = 3 * (std::size_t(y) * width + x);
  return {rgb[p], rgb[p + 1], rgb[p + 2]};
}

// Pixels of the legend's text colour (235 grey) in rows [y0, y1).
int text_pixels(const std::vector<std::uint8_t>& rgb, int width, int y0, int y1) {
  int count = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < width; ++x) count += pixel(rgb, width, x, y) == Pixel{235, 235, 235};
  return count;
}

TEST(CostMap, OneLogScaleFrom1To1024WithALegend) {
  const int w = 300, h = 20;
  std::vector<std::uint32_t> samples(w * h);
  std::vector<std::uint8_t> has_ray(w * h, 1);
  for (int p = 0; p < w * h; ++p)
    samples[p] = 1u << (std::uint32_t(p % w) * 10 / (w - 1));  // 1..1024 along x
  has_ray[0] = 0;
  int out_height = 0;
  const std::vector<std::uint8_t> rgb = cost_map(samples, has_ray, w, h, "samples", out_height);
  int error_height = 0;
  error_heat_map(std::vector<float>(w * h, 1.0f), has_ray, w, h, error_height);
  EXPECT_EQ(out_height, error_height) << "the cost and error maps share one legend strip";
  EXPECT_GT(out_height, h);
  ASSERT_EQ(rgb.size(), 3u * w * out_height);
  EXPECT_EQ(pixel(rgb, w, 0, 0), (Pixel{96, 96, 96})) << "no ray: grey";
  EXPECT_EQ(pixel(rgb, w, 1, 1), (Pixel{68, 1, 84})) << "1 sample: viridis' dark end";
  EXPECT_EQ(pixel(rgb, w, w - 1, 1), (Pixel{253, 231, 37})) << "1024 samples: viridis' bright end";
  // The bar runs from the dark end to the bright end; digits and the unit are drawn below and beside it.
  const int bar_y = h + 1, bar_x0 = w / 20, bar_x1 = bar_x0 + w * 7 / 10 - 1;
  EXPECT_EQ(pixel(rgb, w, bar_x0, bar_y), (Pixel{68, 1, 84}));
  EXPECT_EQ(pixel(rgb, w, bar_x1, bar_y), (Pixel{253, 231, 37}));
  EXPECT_GT(text_pixels(rgb, w, h, out_height), 60) << "tick labels 1 4 16 64 256 1024 and 'samples'";
  EXPECT_EQ(text_pixels(rgb, w, 0, h), 0);
}

// A count has one colour in every cost map, whatever the other counts of its map: maps side by
// side compare by colour. Counts beyond the scale (a 32-bit one too) take its bright end.
TEST(CostMap, ACountHasOneColourInEveryMap) {
  const int w = 256, h = 4;
  std::vector<std::uint8_t> has_ray(w * h, 1);
  std::vector<std::uint32_t> few(w * h, 16), many(w * h, 16);
  for (int p = 0; p < w * h; p += 2) many[p] = 4000000000u;
  int out_height = 0;
  const std::vector<std::uint8_t> a = cost_map(few, has_ray, w, h, "samples", out_height);
  const std::vector<std::uint8_t> b = cost_map(many, has_ray, w, h, "cells", out_height);
  EXPECT_EQ(pixel(a, w, 1, 0), pixel(b, w, 1, 0)) << "16 samples beside 16s and beside 4e9s";
  EXPECT_NE(pixel(a, w, 1, 0), (Pixel{68, 1, 84}));
  EXPECT_EQ(pixel(b, w, 0, 0), (Pixel{253, 231, 37})) << "beyond the scale: its bright end";
  EXPECT_GT(text_pixels(b, w, h, out_height), 0);
}

TEST(CostMap, TraceWritesCostPngBesideErrorPng) {
  const std::string out = test::temp_dir("cost-png");
  const auto r = test::run_cli(
      "trace --res 64 --size 120x72 --technique relief --layers 8-32 --threads 1 --repetitions 1 --out " +
      out);
  ASSERT_EQ(r.status, 0) << r.output;
  auto size_of = [](const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) return std::array<int, 3>{0, 0, 0};
    const OIIO::ImageSpec spec = in->spec();
    return std::array<int, 3>{spec.width, spec.height, spec.nchannels};
  };
  const auto cost = size_of(out + "/cost.png"), error = size_of(out + "/error.png"),
             render = size_of(out + "/render.png");
  EXPECT_EQ(cost[0], 120) << "the view's width";
  EXPECT_EQ(render[1], 72);
  EXPECT_EQ(cost, error) << "the view's size and the same legend strip below it";
  EXPECT_GT(cost[1], 72);
  auto in = OIIO::ImageInput::open(out + "/cost.png");
  ASSERT_TRUE(in);
  std::vector<std::uint8_t> rgb(std::size_t(cost[0]) * cost[1] * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  EXPECT_GT(text_pixels(rgb, cost[0], 72, cost[1]), 20) << "the legend's digits and unit";
}

}  // namespace
}  // namespace heightmarch
