// Trilinear filtering's parts: the mip chain against glGenerateMipmap's box (odd sides too), the
// level of detail against GL's formula (and on views minified by exactly 2 and 4, which must read
// levels 1 and 2 at every ISA), and the gradients a view's pixel grid gives its rays (a view set's
// too).
#include "heightmarch/mip_chain.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "heightmarch/sampler.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

TEST(MipChain, LevelSizesAreGls) {
  EXPECT_EQ(mip_level_count(512, 512), 10);
  EXPECT_EQ(mip_level_count(1, 1), 1);
  EXPECT_EQ(mip_level_count(kMaxDepthMapSide, 3), kMaxMipLevels);
  const std::vector<DepthMap> chain = build_mip_chain(DepthMap{5, 3, std::vector<float>(15, 0.5f)});
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[1].width, 2);
  EXPECT_EQ(chain[1].height, 1);
  EXPECT_EQ(chain[2].width, 1);
  EXPECT_EQ(chain[2].height, 1);
}

TEST(MipChain, TwoByTwoBoxLeavingOddSidesLastOut) {
  // 5 x 3: row j holds 10 j + i. Level 1 (2 x 1) averages texels (0-1, 0-1) and (2-3, 0-1); column
  // 4 and row 2 are left out. Level 2 (1 x 1) reads level 1's one row twice.
  DepthMap map{5, 3, {}};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) map.texels.push_back(float(10 * j + i) / 32.0f);
  const std::vector<DepthMap> chain = build_mip_chain(map);
  EXPECT_EQ(chain[0].texels, map.texels);
  EXPECT_EQ(chain[1].at(0, 0), (0.0f + 1.0f + 10.0f + 11.0f) / 4.0f / 32.0f);
  EXPECT_EQ(chain[1].at(1, 0), (2.0f + 3.0f + 12.0f + 13.0f) / 4.0f / 32.0f);
  EXPECT_EQ(chain[2].at(0, 0), (chain[1].at(0, 0) + chain[1].at(1, 0)) / 2.0f);
}

// Within 2e-7 of log2 and the result's own rounding (half an ulp: 1e-6 near 28).
TEST(MipLog2, WithinTwoTenMillionthsOfLog2AndExactAtPowersOfTwo) {
  for (int e = 0; e <= 28; ++e) EXPECT_EQ(mip_log2(std::ldexp(1.0f, e)), float(e));
  double worst = 0.0;
  for (double x = 1.0; x <= 268435456.0; x *= 1.0001) {
    const float f = float(x), result = mip_log2(f);
    const double rounding = 0.5 * double(std::nextafter(result, 100.0f) - result);
    worst = std::max(worst, std::fabs(double(result) - std::log2(double(f))) - rounding);
  }
  EXPECT_LT(worst, 2e-7);
}

// GL's formula in double: lambda = log2 max(|dT/dx (W, H)|, |dT/dy (W, H)|), clamped to [0, last].
double gl_lod(double du_dx, double dv_dx, double du_dy, double dv_dy, double w, double h, int last) {
  const double rho = std::max(std::hypot(du_dx * w, dv_dx * h), std::hypot(du_dy * w, dv_dy * h));
  return std::clamp(std::log2(rho), 0.0, double(last));
}

TEST(LevelOfDetail, IsGlsFormula) {
  test::Random rng(7);
  for (int k = 0; k < 20000; ++k) {
    const int w = 1 << int(rng.uniform(0.0, 12.0)), h = 1 << int(rng.uniform(0.0, 12.0));
    const int last = mip_level_count(w, h) - 1;
    float g[4];
    for (float& x : g) x = float(rng.uniform(-1.0, 1.0) * std::exp2(rng.uniform(-14.0, 2.0)));
    const float lod = level_of_detail(g[0], g[1], g[2], g[3], float(w), float(h), last);
    ASSERT_NEAR(lod, gl_lod(g[0], g[1], g[2], g[3], w, h, last), 1e-6) << w << "x" << h;
  }
  EXPECT_EQ(level_of_detail(0.0f, 0.0f, 0.0f, 0.0f, 512.0f, 512.0f, 9), 0.0f);  // no footprint: level 0
  EXPECT_EQ(level_of_detail(1.0f, 0.0f, 0.0f, 1.0f, 512.0f, 512.0f, 9), 9.0f);  // a texture a pixel: the last
  EXPECT_EQ(level_of_detail(0.0f, 0.0f, 0.0f, 1.0f / 128.0f, 512.0f, 512.0f, 9), 2.0f);  // the larger axis
}

// A straight-down view of n x n pixels over a 512 x 512 map: each pixel spans 512 / n texels.
TEST(LevelOfDetail, ViewsMinifiedByTwoAndFourReadLevelsOneAndTwo) {
  const DepthMap map = make_builtin_heightfield("terrain", 512, 2);
  const std::vector<DepthMap> chain = build_mip_chain(map);
  for (const auto& [side, level] : {std::pair{256, 1}, {128, 2}}) {
    RayBatch rays = make_view_rays(sweep_view(0.0, side, side));
    // Off the pixel centres, where level 0's bilinear blend equals the levels' texels.
    for (float& t : rays.tx) t += 0.3f / 512.0f;
    for (float& t : rays.ty) t += 0.2f / 512.0f;
    for (std::size_t i = 0; i < rays.size(); ++i)
      ASSERT_EQ(
          level_of_detail(rays.du_dx[i], rays.dv_dx[i], rays.du_dy[i], rays.dv_dy[i], 512.0f, 512.0f, 9),
          float(level));
    TechniqueParams params;
    params.technique = Technique::parallax;  // one sample at T: its depth
    params.filter = Filter::trilinear;
    for (Isa isa : supported_isas()) {
      HitBuffers hits;
      Tracer(map, params, isa).run(rays, hits);
      float apart = 0.0f;  // from level 0's
      for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(hits.depth[i],
                  sample_depth(chain[std::size_t(level)], Wrap::repeat, rays.tx[i], rays.ty[i]))
            << to_string(isa) << " ray " << i;
        apart = std::max(apart,
                         std::fabs(hits.depth[i] - sample_depth(map, Wrap::repeat, rays.tx[i], rays.ty[i])));
      }
      EXPECT_GT(apart, 1e-3f);
    }
  }
}

TEST(PixelGradients, SweepViewStepsOnePixel) {
  const RayBatch rays = make_view_rays(sweep_view(40.0, 64, 32));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_NEAR(rays.du_dx[i], 1.0f / 64.0f, 1e-7f);
    ASSERT_EQ(rays.dv_dx[i], 0.0f);
    ASSERT_EQ(rays.du_dy[i], 0.0f);
    ASSERT_NEAR(rays.dv_dy[i], 1.0f / 32.0f, 1e-7f);
  }
}

// A view set's gradients are its cameras' own: every view of the set around the surface, turned and
// moved on the repeating map (its entry points wrapped modulo 1), keeps the lengths of the single
// view's gradients at the same pixel; none jumps by the wrap or crosses into another view's cell.
TEST(PixelGradients, AViewSetsAreItsCamerasTurnedWithThem) {
  ViewSpec single = default_view(64, 64);
  ViewSpec around = single;
  single = seen_as(single, ViewSet::single());
  around = seen_as(around, ViewSet::around());
  const RayBatch a = make_view_rays(single), b = make_view_rays(around);
  std::map<std::uint32_t, std::size_t> at;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!a.is_padding(i)) at[a.origin[i]] = i;
  ASSERT_GT(b.views, 1u);
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.is_padding(i)) continue;
    const std::size_t j = at.at(b.origin[i]);
    ASSERT_NEAR(std::hypot(b.du_dx[i], b.dv_dx[i]), std::hypot(a.du_dx[j], a.dv_dx[j]), 1e-6) << i;
    ASSERT_NEAR(std::hypot(b.du_dy[i], b.dv_dy[i]), std::hypot(a.du_dy[j], a.dv_dy[j]), 1e-6) << i;
  }
}

// A 4 x 3 grid whose pixels (0, 0), (3, 0), (2, 1) and (3, 1) miss the plane, with T = (10 x + y,
// 100 y + x) at pixel (x, y): the quad partner's difference where it is there, the other side's
// where it is not, zero along an axis with neither.
TEST(PixelGradients, QuadPartnersAndOneSidedWhereTheyMiss) {
  std::vector<float> tx, ty, v0, v1;
  std::vector<std::uint32_t> pixels;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      if ((x == 0 && y == 0) || (x == 3 && y < 2) || (x == 2 && y == 1)) continue;
      tx.push_back(float(10 * x + y));
      ty.push_back(float(100 * y + x));
      v0.push_back(0.0f);
      v1.push_back(1.0f);
      pixels.push_back(std::uint32_t(y * 4 + x));
    }
  RayBatch rays = make_ray_list(tx, ty, v0, v0, v1);
  for (std::size_t i = 0; i < pixels.size(); ++i) rays.origin[i] = pixels[i];
  rays.image_width = 4;
  rays.image_height = 3;
  set_pixel_gradients(rays, 4, 3);
  const auto expect = [&](int x, int y, float du_dx, float dv_dx, float du_dy, float dv_dy) {
    const std::size_t i =
        std::size_t(std::find(pixels.begin(), pixels.end(), std::uint32_t(y * 4 + x)) - pixels.begin());
    ASSERT_LT(i, pixels.size());
    EXPECT_EQ(rays.du_dx[i], du_dx) << x << "," << y;
    EXPECT_EQ(rays.dv_dx[i], dv_dx) << x << "," << y;
    EXPECT_EQ(rays.du_dy[i], du_dy) << x << "," << y;
    EXPECT_EQ(rays.dv_dy[i], dv_dy) << x << "," << y;
  };
  expect(1, 1, 10, 1, 1, 100);  // partners (0, 1) and (1, 0)
  expect(1, 0, 10, 1, 1, 100);  // partner (0, 0) misses: (2, 0) on the other side
  expect(2, 0, 10, 1, 0, 0);    // partner (3, 0) misses: (1, 0); (2, 1) misses, nothing above: 0 in y
  expect(0, 1, 10, 1, 1, 100);  // partner (0, 0) misses: (0, 2) below
  expect(0, 2, 10, 1, 1, 100);  // (0, 3) is off the grid: (0, 1) above
  expect(3, 2, 10, 1, 0, 0);    // (3, 3) is off the grid and (3, 1) misses: 0 in y
  for (std::size_t i = pixels.size(); i < rays.size(); ++i)
    EXPECT_EQ(rays.du_dx[i], rays.du_dx[pixels.size() - 1]);
}

}  // namespace
}  // namespace heightmarch
