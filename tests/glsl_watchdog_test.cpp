// The GLSL watchdog: a brought-in shader whose loop runs on is killed at the draw's bound with an
// InputError, and the runner's next prepare starts a new worker that draws as before.
#include <gtest/gtest.h>

#include <fstream>

#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// At 256x256 rays and one llvmpipe thread this loop (cut by llvmpipe at 65,535 passes) takes
// about 50 s on an AMD EPYC; its bound is 10.5 s.
constexpr const char* kEndless = R"(vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {
  vec2 t = texCoords;
  while (texture(depthMap, t).r < 2.0) t += vec2(1e-7);
  return t;
}
)";

TEST(GlslWatchdog, KillsAnEndlessDrawAndRestarts) {
  const std::string path = test::temp_dir("watchdog") + "/endless.glsl";
  std::ofstream(path) << kEndless;
  const DepthMap map = make_builtin_heightfield("bricks", 64, 1);
  const RayBatch rays = make_view_rays(parse_view("default", 256, 256));
  TechniqueParams params;
  GlslRunner& runner = GlslRunner::instance(1);
  runner.prepare(map, params, rays, path);
  try {
    runner.draw();
    FAIL() << "the endless draw returned";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("endless.glsl: the GLSL draw of 65536 rays ran past its bound of 10.5 s"), std::string::npos)
        << message;
    EXPECT_NE(message.find("restarts"), std::string::npos) << message;
  }
  // A new worker serves the next request as the first did.
  const RayBatch few = make_view_rays(parse_view("default", 32, 32));
  runner.prepare(map, params, few);
  runner.draw();
  HitBuffers glsl, reference;
  bool samples_known = false;
  runner.read(glsl, samples_known);
  Tracer(map, params, Isa::scalar).run(few, reference);
  ASSERT_EQ(glsl.size(), reference.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < few.size(); ++i) same += glsl.samples[i] == reference.samples[i];
  EXPECT_GT(same, few.size() * 9 / 10);
}

}  // namespace
}  // namespace heightmarch
