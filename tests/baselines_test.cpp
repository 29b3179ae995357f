// The baselines on their own, at every ISA of the list the CPU runs (the measurement pass checks
// them again as the suite runs them: tests/measurement_test.cpp): the auto-vectorised and the
// Highway port of the tutorial's POM take the naive port's samples ray by ray and land within
// 0.01 texel of its hits, and the structured Highway POM equals the hand-written POM's scalar
// reference bit for bit. The tracing core's own test, so that the arm64 cross build runs the
// Highway forms at their NEON target under qemu (tests/arm64/).
#include <gtest/gtest.h>

#include "baselines/naive_port.hpp"
#include "baselines/structured_pom.hpp"
#include "heightmarch/metrics.hpp"
#include "heightmarch/tracer.hpp"
#include "heightmarch/views.hpp"

namespace heightmarch {
namespace {

class BaselinesTest : public ::testing::TestWithParam<Isa> {};

// A view of POM at a fixed and a dynamic layer count on two builtins (power-of-two sides, REPEAT:
// what the structured POM takes).
struct PortCase {
  const char* heightfield;
  const char* layers;
};
constexpr PortCase kPortCases[] = {{"bricks", "32"}, {"terrain", "8-32"}};

RayBatch port_rays() {
  ViewSpec view = default_view(96, 80);
  view.tile_size = 16;
  return make_view_rays(view);
}

TEST_P(BaselinesTest, PortsTakeTheNaivePortsSamples) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  const RayBatch rays = port_rays();
  for (const auto& [heightfield, layers] : kPortCases) {
    SCOPED_TRACE(std::string(heightfield) + " pom " + layers);
    const DepthMap map = make_builtin_heightfield(heightfield, 128, 4);
    const LayerSpec l = parse_layer_spec(layers);
    HitBuffers naive, autovec;
    naive_pom(map, rays, l.min_layers, l.max_layers, 0.1f, naive);
    autovec_pom(map, rays, l.min_layers, l.max_layers, 0.1f, isa, autovec);
    std::vector<std::pair<const char*, const HitBuffers*>> ports = {{"auto-vectorised", &autovec}};
    HitBuffers highway;
    if (highway_port_runs(isa)) {
      highway_pom(map, rays, l.min_layers, l.max_layers, 0.1f, isa, highway);
      ports.emplace_back("Highway", &highway);
    }
    for (const auto& [name, hits] : ports)
      for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(hits->samples[i], naive.samples[i]) << name << " port, ray " << i;
        ASSERT_LE(uv_error_texels(hits->u[i], hits->v[i], naive.u[i], naive.v[i], map.width, map.height),
                  1e-2f)
            << name << " port, ray " << i;
      }
  }
}

TEST_P(BaselinesTest, StructuredHighwayPomIsTheScalarReference) {
  const Isa isa = GetParam();
  if (!cpu_supports(isa)) GTEST_SKIP() << "this CPU lacks " << to_string(isa) << ": not tested here";
  if (!highway_structured_runs(isa))
    GTEST_SKIP() << "no structured Highway POM at " << to_string(isa) << " here";
  const RayBatch rays = port_rays();
  for (const auto& [heightfield, layers] : kPortCases) {
    SCOPED_TRACE(std::string(heightfield) + " pom " + layers);
    const DepthMap map = make_builtin_heightfield(heightfield, 128, 4);
    TechniqueParams params;
    params.technique = Technique::pom;
    params.layers = parse_layer_spec(layers);
    HitBuffers reference, structured;
    Tracer(map, params, Isa::scalar).run(rays, reference);
    HighwayStructuredPom(map, params, isa).run(rays, structured);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(structured.samples[i], reference.samples[i]) << "ray " << i;
      ASSERT_EQ(structured.u[i], reference.u[i]) << "ray " << i;
      ASSERT_EQ(structured.v[i], reference.v[i]) << "ray " << i;
      ASSERT_EQ(structured.depth[i], reference.depth[i]) << "ray " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllIsas, BaselinesTest, ::testing::ValuesIn(all_isas()),
                         [](const auto& info) { return std::string(isa_id(info.param)); });

}  // namespace
}  // namespace heightmarch
