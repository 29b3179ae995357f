// Every packet kernel against the scalar reference (the same template at width 1): identical
// sample counts and bit-identical uv, depth, shadow and every other output of the hit list, since
// contraction is off everywhere, under both filters. And the same output for any thread count and tile size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <tuple>
#include <utility>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/tracer.hpp"
#include "heightmarch/views.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// One test per ISA and technique over every layer spec and wrap mode.
using Case = std::tuple<Isa, Technique>;

class PacketKernelTest : public ::testing::TestWithParam<Case> {};

TEST_P(PacketKernelTest, MatchesScalarReference) {
  const auto& [isa, technique] = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  for (auto [label, params] : test::layer_specs_and_wraps(technique)) {
    SCOPED_TRACE(label);
    params.discard = true;
    // Trilinear at two of the layer specs, on a power-of-two map and one whose levels have odd
    // sides (REPEAT wraps it in float): 96 x 80 pixels over them read levels 0 to 3, in packets of
    // one level and of several.
    struct MapCase {
      const char* name;
      int side;
      Filter filter;
    };
    std::vector<MapCase> maps = {{"bricks", 128, Filter::bilinear},
                                 {"terrain", 128, Filter::bilinear},
                                 {"spikes", 128, Filter::bilinear}};
    if (label.rfind("layers 10,", 0) == 0 || label.rfind("layers 8-32,", 0) == 0)
      maps.insert(maps.end(), {{"terrain", 128, Filter::trilinear}, {"bricks", 120, Filter::trilinear}});
    for (const auto& [name, side, filter] : maps) {
      SCOPED_TRACE(to_string(filter));
      params.filter = filter;
      const DepthMap map = make_builtin_heightfield(name, side, 4);
      ViewSpec view = default_view(96, 80);
      view.tile_size = 16;
      const RayBatch rays = make_view_rays(view);
      HitBuffers reference, packet;
      Tracer(map, params, Isa::scalar).run(rays, reference);
      const TraceStats stats = Tracer(map, params, isa).run(rays, packet);
      // Every output of the list (HEIGHTMARCH_HIT_CHANNELS) that HitBuffers holds, a new one too.
      // A structured binding is captured by name only from C++20's clang 16 on: a copy for clang 14.
      const std::string map_name = name;
      HitBuffers::for_each_pair(packet, reference, [&](HitChannel channel, const auto& x, const auto& y) {
        ASSERT_EQ(x.size(), rays.size()) << info(channel).name;
        for (std::size_t i = 0; i < rays.size(); ++i)
          ASSERT_EQ(x[i], y[i]) << map_name << " ray " << i << ": " << info(channel).name;
      });
      EXPECT_GT(stats.simd_utilization(), 0.0);
      EXPECT_LE(stats.simd_utilization(), 1.0);
    }
  }
}

// The pyramid walk (maxmip; the exact reference's float pass runs the same walk) at every ISA
// against scalar on the configurations its rewrites were proved on: every builtin on power-of-two
// and other sides, REPEAT and CLAMP, the default view in tiles of 7, a grazing sweep and the
// window of views around; every output of the hit list, bit for bit.
class WalkEqualityTest : public ::testing::TestWithParam<Isa> {};

TEST_P(WalkEqualityTest, MatchesScalarOnTheWalksConfigurations) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  std::vector<std::pair<std::string, ViewSpec>> views = {{"default, tiles of 7", default_view(40, 36)},
                                                         {"sweep 87", sweep_view(87.0, 32, 32)},
                                                         {"around", default_view(48, 48)}};
  views[0].second.tile_size = 7;
  views[2].second.around = true;
  views[2].second.seed = 3;
  std::size_t rays_checked = 0;
  for (const std::string& name : builtin_heightfield_names())
    for (const auto& [side, wrap] :
         std::vector<std::pair<int, Wrap>>{{64, Wrap::repeat}, {101, Wrap::repeat}, {100, Wrap::clamp}}) {
      const DepthMap map = make_builtin_heightfield(name, side, 4);
      TechniqueParams params;
      params.technique = Technique::maxmip;
      params.wrap = wrap;
      params.discard = true;
      for (const auto& [view_name, view] : views) {
        const std::string where =
            name + " " + std::to_string(side) + (wrap == Wrap::repeat ? " repeat, " : " clamp, ") + view_name;
        const RayBatch rays = make_view_rays(view);
        HitBuffers reference, packet;
        Tracer(map, params, Isa::scalar).run(rays, reference);
        Tracer(map, params, isa).run(rays, packet);
        HitBuffers::for_each_pair(packet, reference, [&](HitChannel channel, const auto& x, const auto& y) {
          ASSERT_EQ(x.size(), rays.size()) << where << ": " << info(channel).name;
          for (std::size_t i = 0; i < rays.size(); ++i)
            ASSERT_EQ(x[i], y[i]) << where << ", ray " << i << ": " << info(channel).name;
        });
        rays_checked += rays.size();
      }
    }
  EXPECT_GT(rays_checked, 0u);
}

INSTANTIATE_TEST_SUITE_P(AllIsas, WalkEqualityTest, ::testing::ValuesIn(test::packet_isas()),
                         [](const ::testing::TestParamInfo<Isa>& info) {
                           return std::string(isa_id(info.param));
                         });

INSTANTIATE_TEST_SUITE_P(AllIsasAllTechniques, PacketKernelTest,
                         ::testing::Combine(::testing::ValuesIn(test::packet_isas()),
                                            ::testing::ValuesIn(test::all_technique_ids())),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(isa_id(std::get<0>(info.param))) + "_" +
                                  test::test_name(to_string(std::get<1>(info.param)));
                         });
// An architecture whose ISA list holds only the scalar reference (arm64) has no packet ISA.
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(PacketKernelTest);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(WalkEqualityTest);

TEST(Determinism, SameHitsForAnyThreadCountAndTileSize) {
  const DepthMap map = make_builtin_heightfield("toybox", 128, 1);
  TechniqueParams params;
  params.technique = Technique::shadow;
  params.layers = parse_layer_spec("8-32");
  ViewSpec view = default_view(200, 150);
  std::vector<float> first;
  for (int threads : {1, 2})
    for (int tile : {7, 16, 64}) {
      const ThreadLimit limit(threads);
      view.tile_size = tile;
      const RayBatch rays = make_view_rays(view);
      HitBuffers hits;
      Tracer(map, params, best_isa()).run(rays, hits);
      std::vector<float> by_pixel(std::size_t(view.width) * view.height * 4, -1.0f);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (rays.is_padding(i)) continue;
        const std::size_t p = rays.origin[i];
        by_pixel[4 * p] = hits.u[i];
        by_pixel[4 * p + 1] = hits.v[i];
        by_pixel[4 * p + 2] = hits.shadow[i];
        by_pixel[4 * p + 3] = float(hits.samples[i]);
      }
      if (first.empty())
        first = by_pixel;
      else
        ASSERT_TRUE(by_pixel == first) << threads << " threads, tile " << tile;
    }
}

TEST(Dispatch, EnvironmentOverrideIsHonoured) {
  setenv("HEIGHTMARCH_ISA", "scalar", 1);
  EXPECT_EQ(select_isa(""), Isa::scalar);
  EXPECT_EQ(select_isa("auto"), best_isa());  // --isa wins over the environment
  setenv("HEIGHTMARCH_ISA", "bogus", 1);
  EXPECT_THROW(select_isa(""), InputError);
  unsetenv("HEIGHTMARCH_ISA");
  EXPECT_EQ(select_isa(""), best_isa());
  for (Isa isa : all_isas())
    if (!cpu_supports(isa)) {
      EXPECT_THROW(parse_isa(to_string(isa)), InputError);
    }
}

// HEIGHTMARCH_MAX_ISA takes the CPU for one whose widest ISA is the cap: every question about
// the ISAs answers as it would there, the Tracer refuses an ISA above it, and the refusal of
// HEIGHTMARCH_ISA names the variable and the ISAs this CPU (so capped) runs.
TEST(Dispatch, EnvironmentCapIsHonoured) {
  const char* set = std::getenv("HEIGHTMARCH_MAX_ISA");  // the capped phase of scripts/test sets it
  const std::string saved = set ? set : "";
  unsetenv("HEIGHTMARCH_MAX_ISA");
  const std::vector<Isa> hardware = supported_isas();
  const DepthMap map = make_builtin_heightfield("flat", 16, 1);
  for (Isa cap : all_isas()) {
    SCOPED_TRACE(to_string(cap));
    setenv("HEIGHTMARCH_MAX_ISA", to_string(cap).c_str(), 1);
    std::vector<Isa> expected;
    for (Isa isa : hardware)
      if (int(isa) <= int(cap)) expected.push_back(isa);
    EXPECT_EQ(supported_isas(), expected);
    EXPECT_EQ(best_isa(), expected.back());
    for (Isa isa : all_isas()) {
      if (cpu_supports(isa)) continue;
      EXPECT_THROW(Tracer(map, TechniqueParams{}, isa), InputError);
      setenv("HEIGHTMARCH_ISA", to_string(isa).c_str(), 1);
      try {
        select_isa("");
        ADD_FAILURE() << "HEIGHTMARCH_ISA=" << to_string(isa) << " accepted";
      } catch (const InputError& e) {
        std::string runs;
        for (Isa r : expected) runs += (runs.empty() ? "" : ", ") + to_string(r);
        EXPECT_NE(
            std::string(e.what()).find("HEIGHTMARCH_ISA=" + to_string(isa) + ": this CPU does not run " +
                                       to_string(isa) + "; it runs " + runs),
            std::string::npos)
            << e.what();
        if (std::find(hardware.begin(), hardware.end(), isa) != hardware.end()) {
          EXPECT_NE(std::string(e.what()).find("capped by HEIGHTMARCH_MAX_ISA=" + to_string(cap)),
                    std::string::npos)
              << e.what();
        }
      }
      unsetenv("HEIGHTMARCH_ISA");
    }
  }
  setenv("HEIGHTMARCH_MAX_ISA", "avx3", 1);
  EXPECT_THROW(best_isa(), InputError);
  setenv("HEIGHTMARCH_MAX_ISA", "", 1);  // empty: no cap
  EXPECT_EQ(supported_isas(), hardware);
  if (saved.empty())
    unsetenv("HEIGHTMARCH_MAX_ISA");
  else
    setenv("HEIGHTMARCH_MAX_ISA", saved.c_str(), 1);
}

}  // namespace
}  // namespace heightmarch
