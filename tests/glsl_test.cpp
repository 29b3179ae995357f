// The GLSL run against the scalar reference, brought-in shaders, and shader errors. Needs no GPU
// and no display: OSMesa renders with llvmpipe on the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/metrics.hpp"
#include "heightmarch/mip_chain.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// GLSL against the scalar reference. llvmpipe's GL_LINEAR rounds differently from the sampling
// formula in the last bit for a few percent of samples (its lerp is fused), which moves POM's hit
// depth by an ulp. Every technique that writes no shadow factor must then still take identical
// sample counts on 99.9% of rays. The soft shadow's loop (as the tutorials write it) runs while
// h - k h / N > 0, whose last step lands within an ulp of 0, so its step count flips by one on a few percent
// of rays (7% on white noise at 4 layers); that step is the k = N one, weighted by 1 - k / N = 0, so it never
// changes the factor. A technique that writes a shadow factor is therefore measured by its factor (agreeing
// within 1e-4 on 99.9% of rays) and by sample counts within one on 99.9% of rays, not by identical
// counts, which the flip dominates: its own search is still held to the 99.9% every technique
// meets, and where that search's one-sample flip meets the shadow's on a ray the two add up.
struct ShadowConformance {
  double same_samples = 0, samples_within_one = 0, same_factor = 0, uv_p99 = 0;
};

ShadowConformance compare_hits(const RayBatch& rays, const HitBuffers& glsl, const HitBuffers& reference,
                               const DepthMap& map) {
  ShadowConformance c;
  std::size_t n = 0, same = 0, within_one = 0, factor = 0;
  std::vector<float> differences;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    ++n;
    same += glsl.samples[i] == reference.samples[i];
    factor += std::fabs(glsl.shadow[i] - reference.shadow[i]) <= 1e-4f;
    within_one +=
        std::max(glsl.samples[i], reference.samples[i]) - std::min(glsl.samples[i], reference.samples[i]) <=
        1;
    differences.push_back(
        uv_error_texels(glsl.u[i], glsl.v[i], reference.u[i], reference.v[i], map.width, map.height));
  }
  std::sort(differences.begin(), differences.end());
  c.same_samples = double(same) / double(n);
  c.samples_within_one = double(within_one) / double(n);
  c.same_factor = double(factor) / double(n);
  c.uv_p99 = differences[differences.size() * 99 / 100];
  return c;
}

// The GLSL run (one llvmpipe thread) of params on rays; whether the worker counted the samples.
HitBuffers glsl_hits(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
                     bool& samples_known) {
  HitBuffers hits;
  GlslRunner& runner = GlslRunner::instance(1);
  runner.prepare(map, params, rays);
  runner.draw();
  runner.read(hits, samples_known);
  return hits;
}

// One test per technique over every layer spec and wrap mode (one process, one worker).
class GlslConformance : public ::testing::TestWithParam<Technique> {};

TEST_P(GlslConformance, MatchesTheScalarReference) {
  const Technique technique = GetParam();
  const DepthMap map = make_builtin_heightfield("bricks", 128, 3);
  const RayBatch rays = make_view_rays(default_view(128, 96));
  // Every layer spec and wrap bilinear, two of them trilinear too (the view reads levels 0 to 2).
  std::vector<std::pair<std::string, TechniqueParams>> cases = test::layer_specs_and_wraps(technique);
  for (auto [label, params] : test::layer_specs_and_wraps(technique))
    if (label.rfind("layers 10,", 0) == 0 || label.rfind("layers 8-32,", 0) == 0) {
      params.filter = Filter::trilinear;
      cases.emplace_back(label + ", trilinear", params);
    }
  for (const auto& [label, params] : cases) {
    SCOPED_TRACE(label);
    HitBuffers reference;
    Tracer(map, params, Isa::scalar).run(rays, reference);
    bool samples_known = false;
    const HitBuffers glsl = glsl_hits(map, params, rays, samples_known);
    ASSERT_TRUE(samples_known);
    const ShadowConformance c = compare_hits(rays, glsl, reference, map);
    if (writes(info(technique), HitChannel::shadow)) {
      // A shadow factor is measured by itself: see ShadowConformance.
      EXPECT_GE(c.same_factor, 0.999) << "share of rays whose shadow factors agree within 1e-4";
      EXPECT_GE(c.samples_within_one, 0.999) << "share of rays whose sample counts are within one";
    } else {
      EXPECT_GE(c.same_samples, 0.999) << "share of rays with identical sample counts";
    }
    EXPECT_LE(c.uv_p99, 1e-3) << "p99 uv difference in texels";
  }
}

// The shadow on a held-out white-noise field at 4 layers, where the flip below is most frequent
// (identical sample counts fall to about 93% of rays there): its factor still agrees.
TEST(GlslShadow, FactorAgreesOnANoiseFieldAtFourLayers) {
  TechniqueParams params;
  params.technique = Technique::shadow;
  params.layers = parse_layer_spec("4");
  DepthMap map{128, 128, std::vector<float>(128 * 128)};
  test::Random rng(17);
  for (float& t : map.texels) t = float(rng.uniform());
  const RayBatch rays = test::random_rays(8192, 75.0, 5);
  HitBuffers reference;
  Tracer(map, params, Isa::scalar).run(rays, reference);
  bool samples_known = false;
  const HitBuffers glsl = glsl_hits(map, params, rays, samples_known);
  const ShadowConformance c = compare_hits(rays, glsl, reference, map);
  EXPECT_GE(c.same_factor, 0.999) << "share of rays whose shadow factors agree within 1e-4";
  EXPECT_GE(c.samples_within_one, 0.999) << "share of rays whose sample counts are within one";
  EXPECT_LE(c.uv_p99, 1e-3) << "p99 uv difference in texels";
}

// A straight-down view of 64 x 64 pixels over a 128 x 128 map reads level 1 (GL's lambda = 1):
// GLSL's trilinear depth at T is level 1's bilinear one, within llvmpipe's fused lerps.
TEST(GlslTrilinear, ViewMinifiedByTwoReadsLevelOne) {
  const DepthMap map = make_builtin_heightfield("terrain", 128, 3);
  const std::vector<DepthMap> chain = build_mip_chain(map);
  RayBatch rays = make_view_rays(sweep_view(0.0, 64, 64));
  // Off the pixel centres, where level 0's bilinear blend is level 1's texel (the 2 x 2 box).
  for (float& t : rays.tx) t += 0.3f / 128.0f;
  for (float& t : rays.ty) t += 0.2f / 128.0f;
  TechniqueParams params;
  params.technique = Technique::parallax;
  params.filter = Filter::trilinear;
  bool samples_known = false;
  const HitBuffers glsl = glsl_hits(map, params, rays, samples_known);
  float worst = 0.0f;
  for (std::size_t i = 0; i < rays.size(); ++i)
    worst = std::max(worst,
                     std::fabs(glsl.depth[i] - sample_depth(chain[1], Wrap::repeat, rays.tx[i], rays.ty[i])));
  EXPECT_LE(worst, 1e-6f);
  // and not level 0's
  float apart = 0.0f;
  for (std::size_t i = 0; i < rays.size(); ++i)
    apart =
        std::max(apart, std::fabs(glsl.depth[i] - sample_depth(map, Wrap::repeat, rays.tx[i], rays.ty[i])));
  EXPECT_GT(apart, 1e-2f);
}

INSTANTIATE_TEST_SUITE_P(AllTechniques, GlslConformance, ::testing::ValuesIn(test::all_technique_ids()),
                         [](const auto& info) { return test::test_name(to_string(info.param)); });

// One worker process per llvmpipe thread count: both counts run in this process, on the same
// rays, and agree bit for bit.
TEST(GlslRunner, OneAndTwoThreadsInOneProcessGiveIdenticalHits) {
  TechniqueParams params;
  params.technique = Technique::shadow;  // POM's hit and the shadow march: every output is written
  const DepthMap map = make_builtin_heightfield("bricks", 128, 3);
  const RayBatch rays = make_view_rays(default_view(128, 96));
  HitBuffers hits[2];
  GlslRunner* runners[2] = {&GlslRunner::instance(1), &GlslRunner::instance(2)};
  ASSERT_NE(runners[0], runners[1]);
  for (int t = 0; t < 2; ++t) {
    GlslRunner& runner = *runners[t];
    EXPECT_EQ(runner.threads(), t + 1);
    EXPECT_NE(runner.renderer().renderer.find("llvmpipe"), std::string::npos) << runner.renderer().renderer;
    runner.prepare(map, params, rays);
    runner.draw();
    const double seconds = runner.draw().wall_seconds;
    EXPECT_GT(seconds, 0.0);
    EXPECT_LT(seconds, 60.0);
    bool samples_known = false;
    runner.read(hits[t], samples_known);
    EXPECT_TRUE(samples_known);
    ASSERT_EQ(hits[t].size(), rays.size());
  }
  EXPECT_EQ(&GlslRunner::instance(2), runners[1]) << "a thread count keeps its runner";
  EXPECT_EQ(hits[0].u, hits[1].u);
  EXPECT_EQ(hits[0].v, hits[1].v);
  EXPECT_EQ(hits[0].depth, hits[1].depth);
  EXPECT_EQ(hits[0].samples, hits[1].samples);
  EXPECT_EQ(hits[0].shadow, hits[1].shadow);
  EXPECT_EQ(hits[0].discarded, hits[1].discarded);
}

// Draws once and reads the hits back.
HitBuffers draw_and_read(GlslRunner& runner) {
  runner.draw();
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  return hits;
}

void expect_same_hits(const HitBuffers& a, const HitBuffers& b, const std::string& what) {
  EXPECT_EQ(a.u, b.u) << what;
  EXPECT_EQ(a.v, b.v) << what;
  EXPECT_EQ(a.depth, b.depth) << what;
  EXPECT_EQ(a.samples, b.samples) << what;
  EXPECT_EQ(a.shadow, b.shadow) << what;
  EXPECT_EQ(a.discarded, b.discarded) << what;
}

// The suite prepares configuration after configuration on one scene: the client sends the depth
// map and rays only when their contents change, and the worker keeps linked programs. Neither
// may change a hit. The references come from another worker (3 threads), each after a decoy scene,
// so their map and rays are uploaded afresh.
TEST(GlslRunner, RepeatedPreparesOnOneSceneGiveTheHitsOfFreshOnes) {
  const DepthMap map = make_builtin_heightfield("bricks", 128, 3);
  const DepthMap other_map = make_builtin_heightfield("bricks", 128, 4);
  const RayBatch rays = make_view_rays(default_view(128, 96));
  RayBatch other_rays = rays;  // the view transposed: the same sizes, other rays
  other_rays.tx = rays.ty;
  other_rays.ty = rays.tx;
  other_rays.vx = rays.vy;
  other_rays.vy = rays.vx;
  const DepthMap decoy_map = make_builtin_heightfield("bricks", 16, 1);
  const RayBatch decoy_rays = make_view_rays(default_view(8, 8));
  GlslRunner& fresh_runner = GlslRunner::instance(3);
  auto fresh = [&](const DepthMap& m, const TechniqueParams& p, const RayBatch& r) {
    fresh_runner.prepare(decoy_map, p, decoy_rays);
    fresh_runner.prepare(m, p, r);
    return draw_and_read(fresh_runner);
  };
  // Two techniques, each in both wrap modes; the shadow march also reads the light; and POM and
  // cone stepping trilinear (the mip chains uploaded, then left out by the bilinear ones).
  std::vector<TechniqueParams> cases(6);
  cases[0].technique = cases[2].technique = cases[4].technique = Technique::pom;
  cases[1].technique = cases[3].technique = Technique::shadow;
  cases[5].technique = Technique::cone;
  cases[1].wrap = cases[2].wrap = cases[5].wrap = Wrap::clamp;
  cases[4].filter = cases[5].filter = Filter::trilinear;
  std::vector<HitBuffers> references;
  for (const TechniqueParams& p : cases) references.push_back(fresh(map, p, rays));
  ASSERT_NE(references[0].u, references[2].u) << "the scene must tell the wrap modes apart";
  ASSERT_NE(references[0].u, references[4].u) << "the scene must tell the filters apart";

  GlslRunner& runner = GlslRunner::instance(1);
  for (int round = 0; round < 3; ++round)
    for (std::size_t c = 0; c < cases.size(); ++c) {
      runner.prepare(map, cases[c], rays);
      expect_same_hits(draw_and_read(runner), references[c],
                       "round " + std::to_string(round) + ", case " + std::to_string(c));
    }

  // New contents in the same buffers (a pointer says nothing), after a cached prepare.
  DepthMap scene_map = map;
  RayBatch scene_rays = rays;
  runner.prepare(scene_map, cases[3], scene_rays);
  const float* texels = scene_map.texels.data();
  scene_map.texels = other_map.texels;
  ASSERT_EQ(scene_map.texels.data(), texels);
  runner.prepare(scene_map, cases[3], scene_rays);
  const HitBuffers new_map = fresh(other_map, cases[3], rays);
  ASSERT_NE(new_map.u, references[3].u);
  expect_same_hits(draw_and_read(runner), new_map, "new depth map");
  scene_rays.tx = other_rays.tx;
  scene_rays.ty = other_rays.ty;
  scene_rays.vx = other_rays.vx;
  scene_rays.vy = other_rays.vy;
  scene_rays.vz = other_rays.vz;
  runner.prepare(scene_map, cases[3], scene_rays);
  const HitBuffers new_rays = fresh(other_map, cases[3], other_rays);
  ASSERT_NE(new_rays.u, new_map.u);
  expect_same_hits(draw_and_read(runner), new_rays, "new rays");
  runner.prepare(map, cases[0], rays);
  expect_same_hits(draw_and_read(runner), references[0], "the first scene again");
}

// A compile error in the worker comes back as an InputError naming the file and line, and the
// worker stays usable.
TEST(GlslRunner, ShaderSyntaxErrorIsAnInputErrorAndTheWorkerLives) {
  const std::string dir = test::temp_dir("glsl-runner-bad");
  const std::string path = dir + "/bad.glsl";
  std::ofstream(path) << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)\n{\n  return texCoords +;\n}\n";
  const DepthMap map = make_builtin_heightfield("bricks", 32, 1);
  const RayBatch rays = make_view_rays(default_view(8, 8));
  GlslRunner& runner = GlslRunner::instance(1);
  try {
    runner.prepare(map, TechniqueParams(), rays, path);
    FAIL() << "a syntax error compiled";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path + ":3:"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  runner.prepare(map, TechniqueParams(), rays);
  runner.draw();
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  EXPECT_EQ(hits.size(), rays.size());
}

// Thread counts no other test asks for: a runner that failed to start is not kept, but one that
// started would be.
TEST(GlslRunner, MissingWorkerIsAClearError) {
  const test::ScopedEnv env("HEIGHTMARCH_GLSL_WORKER", "/nonexistent");
  try {
    GlslRunner::instance(5);
    FAIL() << "a missing worker started";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("GLSL worker /nonexistent"), std::string::npos) << message;
    EXPECT_NE(message.find("cannot start"), std::string::npos) << message;
  }
  const auto r = test::run_cli("glsl --res 16 --size 8x8 --threads 1");
  EXPECT_EQ(r.status, 1) << r.output;
  // The tool's first question to the worker is which GL paths it has.
  EXPECT_EQ(
      r.output.rfind("heightmarch: GLSL worker /nonexistent (asked which GL paths it has): cannot start", 0),
      0u)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

TEST(GlslRunner, WorkerThatExitsIsAClearError) {
  const test::ScopedEnv env("HEIGHTMARCH_GLSL_WORKER", "/bin/true");
  try {
    GlslRunner::instance(6);
    FAIL() << "/bin/true answered as a worker";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("GLSL worker /bin/true (6 threads)"), std::string::npos) << message;
    EXPECT_NE(message.find("exited with status 0"), std::string::npos) << message;
  }
}

// LearnOpenGL's steep parallax function, pasted as the tutorial writes it (with its own uniform
// declarations and names).
constexpr const char* kTutorialShader = R"(#version 330 core
uniform sampler2D depthMap;
uniform float height_scale;

vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
{
    // number of depth layers
    const float minLayers = 8;
    const float maxLayers = 32;
    float numLayers = mix(maxLayers, minLayers, abs(dot(vec3(0.0, 0.0, 1.0), viewDir)));
    float layerDepth = 1.0 / numLayers;
    float currentLayerDepth = 0.0;
    vec2 P = viewDir.xy / viewDir.z * height_scale;
    vec2 deltaTexCoords = P / numLayers;
    vec2  currentTexCoords     = texCoords;
    float currentDepthMapValue = texture(depthMap, currentTexCoords).r;
    while(currentLayerDepth < currentDepthMapValue)
    {
        currentTexCoords -= deltaTexCoords;
        currentDepthMapValue = texture(depthMap, currentTexCoords).r;
        currentLayerDepth += layerDepth;
    }
    return currentTexCoords;
}
)";

TEST(GlslShaderFile, TutorialShaderRunsAndIsMeasured) {
  const std::string dir = test::temp_dir("glsl-shader");
  std::ofstream(dir + "/steep.glsl") << kTutorialShader;
  const auto r = test::run_cli("glsl --res 64 --size 64x48 --layers 8-32 --threads 1 --shader " + dir +
                               "/steep.glsl --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("samples/ray unknown"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("uv error (texels)"), std::string::npos) << r.output;
  std::ifstream json(dir + "/out/metrics.json");
  const std::string text((std::istreambuf_iterator<char>(json)), {});
  EXPECT_NE(text.find("\"backend\": \"glsl\""), std::string::npos) << text;
}

TEST(GlslShaderFile, SyntaxErrorNamesTheLine) {
  const std::string dir = test::temp_dir("glsl-bad");
  std::ofstream(dir + "/bad.glsl")
      << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)\n{\n  return texCoords +;\n}\n";
  const auto r = test::run_cli("glsl --res 16 --size 8x8 --threads 1 --shader " + dir + "/bad.glsl");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("bad.glsl:3:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.rfind("heightmarch: ", 0), 0u) << r.output;
}

// A loop that runs on until llvmpipe cuts it (65,535 passes) and leaves uv infinite: reported, not
// measured. (A `while (true)` without an exit is no test: its result is undefined, and Mesa's
// compiler returned NaN on one CPU and finite garbage on another.)
TEST(GlslShaderFile, RunawayLoopIsReportedNotMeasured) {
  const std::string dir = test::temp_dir("glsl-forever");
  std::ofstream(dir + "/forever.glsl")
      << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)\n{\n  vec2 uv = texCoords;\n"
         "  for (int i = 0; i >= 0; ++i) uv = uv * 2.0 + 1.0;\n  return uv;\n}\n";
  const auto r = test::run_cli("glsl --res 16 --size 16x16 --threads 1 --shader " + dir + "/forever.glsl");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("non-finite uv"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("nan"), std::string::npos) << r.output;
}

// A very long line (once a stack overflow in the line filter's regex) is read like any other,
// and the file's own declarations of the harness's uniforms are still dropped.
TEST(GlslShaderFile, LongLinesAndOwnUniformDeclarations) {
  const std::string dir = test::temp_dir("glsl-long");
  std::ofstream(dir + "/long.glsl") << "#version 330 //" << std::string(40000, 'x') << "\n"
                                    << "  uniform float heightScale ;\nuniform sampler2D depthMap;\n"
                                    << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { // "
                                    << std::string(40000, 'y') << "\n  return texCoords;\n}\n";
  const auto r = test::run_cli("glsl --res 16 --size 8x8 --threads 1 --shader " + dir + "/long.glsl");
  EXPECT_EQ(r.status, 0) << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find("uv error (texels)"), std::string::npos) << r.output.substr(0, 2000);
}

TEST(GlslShaderFile, MissingAndEmptyFiles) {
  const std::string dir = test::temp_dir("glsl-missing");
  std::ofstream(dir + "/empty.glsl") << "\n";
  auto r = test::run_cli("glsl --res 16 --size 8x8 --shader " + dir + "/nope.glsl");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("cannot open shader file"), std::string::npos) << r.output;
  r = test::run_cli("glsl --res 16 --size 8x8 --shader " + dir + "/empty.glsl");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("empty shader file"), std::string::npos) << r.output;
  // what follows a NUL byte was dropped unread, and the rest ran as if it were the whole file
  std::ofstream(dir + "/nul.glsl", std::ios::binary) << std::string(
      "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { return texCoords; }\n\0 garbage\n", 83);
  r = test::run_cli("glsl --res 16 --size 8x8 --shader " + dir + "/nul.glsl");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("nul.glsl: holds a NUL byte (line 2)"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace heightmarch
