// Brought-in shaders named as themselves (console, metrics.json, benchmark names), never as the
// default technique; figures nobody measured read "unknown" and are written as null; --compare
// against a named technique or, for a shader, every technique with the closest named; and --json
// writing exactly one JSON document on stdout. Needs no GPU (llvmpipe).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "experiment/configuration.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// The tutorial's plain parallax function: the same uvs as the CPU's parallax technique.
constexpr const char* kPlainParallax = R"(uniform sampler2D depthMap;
uniform float heightScale;
vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)
{
    float height = texture(depthMap, texCoords).r;
    return texCoords - viewDir.xy / viewDir.z * (height * heightScale);
}
)";

std::string write_shader(const std::string& dir) {
  const std::string path = dir + "/mine.glsl";
  std::ofstream(path) << kPlainParallax;
  return path;
}

// Runs the CLI with stdout into `json_path` (stderr stays in the result's output).
test::CliResult run_cli_json(const std::string& arguments, const std::string& json_path) {
  return test::run_command(std::string(HEIGHTMARCH_CLI) + " " + arguments + " > " + json_path);
}

// Parses the file as exactly one JSON document (Python's json.load refuses anything after it)
// and prints `expression` of it, `d`; "INVALID: ..." when it is not one document.
std::string json_query(const std::string& path, const std::string& expression) {
  const std::string program =
      "import json,sys\n"
      "try:\n  d = json.load(open(sys.argv[1]))\n"
      "except ValueError as e:\n  print('INVALID: %s' % e); sys.exit(0)\n"
      "print(json.dumps(" +
      expression + "))\n";
  const std::string program_path = path + ".py";
  std::ofstream(program_path) << program;
  std::string out = test::run_command("/usr/bin/python3 " + program_path + " " + path).output;
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

TEST(ShaderLabel, LabelAndBenchmarkNameAreTheShaders) {
  Configuration c;
  c.kind = RunKind::glsl;
  c.heightfield = parse_heightfield("builtin:bricks", 64);
  c.view = default_view(48, 40);
  c.params.technique = Technique::pom;
  c.params.layers = parse_layer_spec("32");
  EXPECT_EQ(c.label(), "pom");
  const std::string technique_name = benchmark_name(c, 64, 64);
  c.shader = BroughtInShader{"some/dir/mine.glsl"};
  EXPECT_FALSE(c.has_technique());
  EXPECT_EQ(c.label(), "shader:mine.glsl");
  c.gl.path = GlPath::osmesa;
  EXPECT_EQ(benchmark_name(c, 64, 64),
            "BM_GLSL/heightfield:bricks/shader:mine.glsl/layers:32/isa:glsl/threads:1/gl:osmesa/view:48x40/"
            "depth_map:64x64");
  EXPECT_NE(benchmark_name(c, 64, 64), technique_name);
  // Another GL target is another measurement, named apart.
  Configuration egl = c;
  egl.gl = {GlPath::egl, "software"};
  EXPECT_FALSE(c.same_measurement(egl));
  EXPECT_NE(benchmark_name(egl, 64, 64).find("/threads:1/gl:egl@software/view:"), std::string::npos);
  Configuration other = c;
  other.shader = BroughtInShader{"other.glsl"};
  EXPECT_FALSE(c.same_measurement(other));
}

TEST(ShaderLabel, ConsoleAndMetricsNameTheShaderAndUnknownFigures) {
  const std::string dir = test::temp_dir("shader-label");
  const std::string shader = write_shader(dir);
  const auto r = test::run_cli("glsl --res 64 --size 48x40 --threads 1 --repetitions 1 --shader " + shader +
                               " --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("shader:mine.glsl layers 32 on builtin:bricks"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("pom"), std::string::npos) << r.output;
  for (const char* unknown : {"samples/ray unknown", "Msamples/s unknown", "SIMD use unknown"})
    EXPECT_NE(r.output.find(unknown), std::string::npos) << unknown << "\n" << r.output;
  EXPECT_EQ(r.output.find("0.00 samples/ray"), std::string::npos) << r.output;
  const std::string metrics = dir + "/out/metrics.json";
  EXPECT_EQ(json_query(metrics, "[d['technique'], d['shader']]"),
            "[null, {\"path\": \"" + shader + "\", \"label\": \"shader:mine.glsl\"}]");
  EXPECT_EQ(
      json_query(metrics, "[d['samples'], d['samples_known'], d['samples_per_ray'], d['simd_utilization']]"),
      "[null, false, null, null]");
  EXPECT_EQ(json_query(metrics, "d['speed']['samples_per_second']"), "null");
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/error.png"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/cost.png")) << "a cost map of unknown sample counts";
}

TEST(ShaderLabel, TechniqueRowsSayWhatTheyAre) {
  const std::string dir = test::temp_dir("technique-label");
  const auto r = run_cli_json(
      "trace --res 64 --size 48x40 --threads 1 --repetitions 1 --technique steep --json", dir + "/t.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(json_query(dir + "/t.json",
                       "[d['technique'], d['shader'], d['samples_known'], d['simd_utilization'] > 0]"),
            "[\"steep\", null, true, true]");
}

TEST(ShaderLabel, ShaderAndTechniqueExcludeEachOther) {
  const std::string dir = test::temp_dir("shader-technique");
  const auto r = test::run_cli("glsl --res 16 --size 8x8 --technique steep --shader " + write_shader(dir));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output.rfind("heightmarch: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("excludes"), std::string::npos) << r.output;
}

TEST(GlslJson, OneDocumentWithAndWithoutCompare) {
  const std::string dir = test::temp_dir("glsl-json");
  const std::string common = "glsl --res 32 --size 24x16 --threads 1 --repetitions 1 --layers 8 --json";
  auto r = run_cli_json(common, dir + "/alone.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(json_query(dir + "/alone.json", "[d['kind'], d['technique']]"), "[\"glsl\", \"pom\"]");
  r = run_cli_json(common + " --compare", dir + "/compare.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(
      json_query(dir + "/compare.json",
                 "[d['glsl']['technique'], [c['cpu']['technique'] for c in d['comparisons']], d['closest'],"
                 " d['comparisons'][0]['conformance']['identical_sample_counts'] > 0.9]"),
      "[\"pom\", [\"pom\"], \"pom\", true]");
  // --compare before --json: the option's value is optional, so --json stays a flag.
  r = run_cli_json("glsl --res 32 --size 24x16 --threads 1 --repetitions 1 --compare --json",
                   dir + "/before.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(json_query(dir + "/before.json", "len(d['comparisons'])"), "1");
}

TEST(GlslCompare, NamedTechnique) {
  const std::string dir = test::temp_dir("compare-named");
  const std::string shader = write_shader(dir);
  const auto r = run_cli_json(
      "glsl --res 32 --size 24x16 --threads 1 --repetitions 1 --shader " + shader + " --compare steep --json",
      dir + "/c.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(
      json_query(
          dir + "/c.json",
          "[d['glsl']['shader']['label'], [c['cpu']['technique'] for c in d['comparisons']], d['closest'],"
          " d['comparisons'][0]['conformance']['identical_sample_counts'],"
          " d['comparisons'][0]['cpu']['layers']]"),
      "[\"shader:mine.glsl\", [\"steep\"], \"steep\", null, \"32\"]");
}

TEST(GlslCompare, ShaderAgainstEveryTechniqueNamesTheClosest) {
  const std::string dir = test::temp_dir("compare-every");
  const std::string shader = write_shader(dir);
  const std::string common =
      "glsl --res 32 --size 24x16 --threads 1 --repetitions 1 --shader " + shader + " --compare";
  auto r = run_cli_json(common + " --json", dir + "/c.json");
  ASSERT_EQ(r.status, 0) << r.output;
  std::string every;
  for (const TechniqueInfo& t : techniques())
    every += std::string(every.empty() ? "" : ", ") + "\"" + std::string(t.name) + "\"";
  EXPECT_EQ(json_query(dir + "/c.json", "[c['cpu']['technique'] for c in d['comparisons']]"),
            "[" + every + "]");
  EXPECT_EQ(json_query(dir + "/c.json", "d['closest']"), "\"parallax\"");
  EXPECT_EQ(json_query(dir + "/c.json",
                       "all(c['conformance']['uv_difference_p99'] >= 0 and c['cpu_over_glsl_rays_per_second']"
                       "['median'] > 0 for c in d['comparisons'])"),
            "true");
  r = test::run_cli(common);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("conformance of shader:mine.glsl with relief ("), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("closest technique to shader:mine.glsl: parallax"), std::string::npos) << r.output;
}

TEST(GlslCompare, UnknownTechniqueIsOneLine) {
  const auto r = test::run_cli("glsl --res 16 --size 8x8 --threads 1 --compare nope");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output.rfind("heightmarch: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("nope"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

}  // namespace
}  // namespace heightmarch
