// The sampler: the sampling formula (docs/conventions.md) against hand-computed values, and the packet
// sampler of every ISA against the sampling formula (docs/conventions.md), bit for bit, on scattered and on
// clustered packets.
#include "heightmarch/sampler.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "heightmarch/mip_chain.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// 3 x 2 texels: row 0 = 0.0 0.2 0.4, row 1 = 0.6 0.8 1.0.
DepthMap small_map() { return DepthMap{3, 2, {0.0f, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f}}; }

TEST(Sampler, TexelCentresReturnTexels) {
  const DepthMap map = small_map();
  for (Wrap wrap : {Wrap::repeat, Wrap::clamp})
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(sample_depth(map, wrap, (i + 0.5f) / 3.0f, (j + 0.5f) / 2.0f), map.at(i, j));
}

TEST(Sampler, HandComputedBlends) {
  const DepthMap map = small_map();
  // Halfway between texel (0,0) and (1,0) horizontally, on row 0's centre: (0 + 0.2) / 2.
  EXPECT_NEAR(sample_depth(map, Wrap::repeat, 1.0f / 3.0f, 0.25f), 0.1f, 1e-6f);
  // The centre of the 2 x 2 block (0,0)-(1,1): (0 + 0.2 + 0.6 + 0.8) / 4.
  EXPECT_NEAR(sample_depth(map, Wrap::repeat, 1.0f / 3.0f, 0.5f), 0.4f, 1e-6f);
  // u = 0: halfway between the last and the first column under REPEAT ...
  EXPECT_NEAR(sample_depth(map, Wrap::repeat, 0.0f, 0.25f), 0.2f, 1e-6f);
  // ... and the first column under CLAMP.
  EXPECT_NEAR(sample_depth(map, Wrap::clamp, 0.0f, 0.25f), 0.0f, 1e-6f);
  // v = 1: halfway between rows 1 and 0 under REPEAT, row 1 under CLAMP (column 2's centre).
  EXPECT_NEAR(sample_depth(map, Wrap::repeat, 2.5f / 3.0f, 1.0f), 0.7f, 1e-6f);
  EXPECT_NEAR(sample_depth(map, Wrap::clamp, 2.5f / 3.0f, 1.0f), 1.0f, 1e-6f);
  // Far outside: REPEAT wraps whole periods, CLAMP holds the edge.
  EXPECT_NEAR(sample_depth(map, Wrap::repeat, 5.0f + 1.0f / 3.0f, 7.25f), 0.1f, 1e-5f);
  EXPECT_EQ(sample_depth(map, Wrap::clamp, -4.0f, -3.0f), 0.0f);
  EXPECT_EQ(sample_depth(map, Wrap::clamp, 9.0f, 9.0f), 1.0f);
}

// The packet sampler is reached through the parallax kernel: its depth output is one sample at T.
class PacketSamplerTest : public ::testing::TestWithParam<Isa> {};

// Plain parallax's depth is one read of D at T: the packet sampler's bits against the formula's,
// in both wraps.
void expect_parallax_reads_the_formula(const DepthMap& map, const RayBatch& rays, Isa isa) {
  for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
    TechniqueParams params;
    params.technique = Technique::parallax;
    params.wrap = wrap;
    HitBuffers hits;
    Tracer(map, params, isa).run(rays, hits);
    for (std::size_t i = 0; i < rays.size(); ++i)
      ASSERT_EQ(hits.depth[i], sample_depth(map, wrap, rays.tx[i], rays.ty[i]))
          << to_string(isa) << " " << map.width << "x" << map.height << " at (" << rays.tx[i] << ", "
          << rays.ty[i] << ")";
  }
}

TEST_P(PacketSamplerTest, BitIdenticalToSpecFormula) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  for (const auto& [w, h] : {std::pair{3, 2}, {17, 5}, {64, 64}, {1, 1}, {256, 7}}) {
    DepthMap map{w, h, {}};
    test::Random rng(w * 1000 + h);
    for (int k = 0; k < w * h; ++k) map.texels.push_back(float(rng.uniform()));
    std::vector<float> tx, ty, vx, vy, vz;
    for (int k = 0; k < 4000; ++k) {
      tx.push_back(float(rng.uniform(-20.0, 20.0)));
      ty.push_back(float(rng.uniform(-20.0, 20.0)));
      vx.push_back(0.0f);
      vy.push_back(0.0f);
      vz.push_back(1.0f);
    }
    const RayBatch rays = make_ray_list(tx, ty, vx, vy, vz);
    expect_parallax_reads_the_formula(map, rays, isa);
  }
}

// Packets whose taps cluster within a few texels, as a layer step of a pixel block's rays does
// (the coherent fetch of vfloat16_avx512.hpp), spread from one texel to beyond its window, near
// every edge of the texture and across the REPEAT seam: the same bits as the formula.
TEST_P(PacketSamplerTest, BitIdenticalOnClusteredPackets) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  for (const auto& [w, h] : {std::pair{64, 64}, {37, 9}, {8, 5}, {7, 4}, {512, 3}}) {
    DepthMap map{w, h, {}};
    test::Random rng(w * 7 + h);
    for (int k = 0; k < w * h; ++k) map.texels.push_back(float(rng.uniform()));
    std::vector<float> tx, ty, zero(32 * 400, 0.0f), one(32 * 400, 1.0f);
    for (int packet = 0; packet < 400; ++packet) {
      // a centre anywhere, edges and the seam included, and a spread of 0 to 10 texels
      const double cu = rng.uniform(-1.1, 2.1), cv = rng.uniform(-1.1, 2.1),
                   spread = 10.0 * rng.uniform() * rng.uniform();
      for (int lane = 0; lane < 32; ++lane) {
        tx.push_back(float(cu + spread * rng.uniform(-0.5, 0.5) / w));
        ty.push_back(float(cv + spread * rng.uniform(-0.5, 0.5) / h));
      }
    }
    const RayBatch rays = make_ray_list(tx, ty, zero, zero, one);
    expect_parallax_reads_the_formula(map, rays, isa);
  }
}

// Trilinear: parallax's depth is one read of the mip chain at T, at the level of detail of the ray's
// gradients: the same bits as the formula (sample_depth over build_mip_chain) at every ISA, on
// packets whose lanes share a level (the coherent fetch) and packets whose lanes read different
// levels (gathered), on power-of-two and other sides (odd levels), in both wraps.
TEST_P(PacketSamplerTest, TrilinearBitIdenticalToSpecFormula) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  for (const auto& [w, h] : {std::pair{64, 64}, {37, 9}, {1, 1}, {256, 7}}) {
    DepthMap map{w, h, {}};
    test::Random rng(w * 31 + h);
    for (int k = 0; k < w * h; ++k) map.texels.push_back(float(rng.uniform()));
    const std::vector<DepthMap> chain = build_mip_chain(map);
    const int last = int(chain.size()) - 1;
    std::vector<float> tx, ty, zero(32 * 200, 0.0f), one(32 * 200, 1.0f);
    std::vector<float> gradients[4];
    for (int packet = 0; packet < 200; ++packet) {
      const double cu = rng.uniform(-1.1, 2.1), cv = rng.uniform(-1.1, 2.1);
      const bool shared = packet % 2 == 0;  // one footprint for the packet's lanes, or one each
      double g[4] = {};
      for (int lane = 0; lane < 32; ++lane) {
        tx.push_back(float(cu + 3.0 * rng.uniform(-0.5, 0.5) / w));
        ty.push_back(float(cv + 3.0 * rng.uniform(-0.5, 0.5) / h));
        if (lane == 0 || !shared)
          for (double& x : g) x = rng.uniform(-1.0, 1.0) * std::exp2(rng.uniform(-10.0, 1.0));
        for (int k = 0; k < 4; ++k) gradients[k].push_back(float(g[k]));
      }
    }
    RayBatch rays = make_ray_list(tx, ty, zero, zero, one);
    rays.du_dx = gradients[0];
    rays.dv_dx = gradients[1];
    rays.du_dy = gradients[2];
    rays.dv_dy = gradients[3];  // 6400 rays: whole tiles, no padding
    for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
      TechniqueParams params;
      params.technique = Technique::parallax;
      params.wrap = wrap;
      params.filter = Filter::trilinear;
      HitBuffers hits;
      Tracer(map, params, isa).run(rays, hits);
      for (std::size_t i = 0; i < gradients[0].size(); ++i) {
        const float lod = level_of_detail(rays.du_dx[i], rays.dv_dx[i], rays.du_dy[i], rays.dv_dy[i],
                                          float(w), float(h), last);
        ASSERT_EQ(hits.depth[i], sample_depth(chain, wrap, rays.tx[i], rays.ty[i], lod))
            << to_string(isa) << " " << w << "x" << h << " ray " << i << " at lod " << lod;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, PacketSamplerTest, ::testing::ValuesIn(all_isas()),
                         [](const auto& info) { return std::string(isa_id(info.param)); });

}  // namespace
}  // namespace heightmarch
