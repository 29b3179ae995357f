// build/heightmarch-bench: Google Benchmark over techniques x layers x ISA x threads on the
// default view of each heightfield. Each entry's name encodes its configuration; its counters
// carry speed and accuracy (SPEC section 6). A kernel is checked against the scalar reference
// before it is timed: a wrong kernel never produces a number.
//
// Own flags, after Google Benchmark's: --hm_size=N (view side, default 1024),
// --hm_res=N (depth map side, default 512), --hm_heightfields=bricks,terrain,
// --hm_threads=1,2 (default 1 and all cores), --hm_isas=scalar,avx2 (default all the CPU runs),
// --hm_layers=4,8,32,8-32 (layer specs of BM_Trace and BM_GLSL), --hm_min_time=0.2 (seconds per
// benchmark), --hm_glsl_threads=N (llvmpipe threads, fixed per process; default the most of --hm_threads).
// A heightfield is a builtin name or a depth map file.
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "bench_registry.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"
#include "io/provenance.hpp"

namespace {

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace heightmarch;
  benchmark::Initialize(&argc, argv);
  bench::BenchConfig config;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto value = [&](const char* name) -> const char* {
        const std::string prefix = std::string("--") + name + "=";
        return arg.rfind(prefix, 0) == 0 ? argv[i] + prefix.size() : nullptr;
      };
      if (const char* v = value("hm_size")) config.view_size = std::stoi(v);
      else if (const char* v = value("hm_res")) config.resolution = std::stoi(v);
      else if (const char* v = value("hm_heightfields")) config.heightfields = split(v);
      else if (const char* v = value("hm_layers")) config.layer_specs = split(v);
      else if (const char* v = value("hm_min_time")) config.min_time = std::stod(v);
      else if (const char* v = value("hm_glsl_threads")) config.glsl_threads = std::stoi(v);
      else if (const char* v = value("hm_threads")) {
        config.threads.clear();
        for (const auto& t : split(v)) config.threads.push_back(std::stoi(t));
      } else if (const char* v = value("hm_isas")) {
        config.isas.clear();
        for (const auto& name : split(v)) config.isas.push_back(parse_isa(name));
      } else {
        std::fprintf(stderr, "heightmarch-bench: unknown option %s\n", argv[i]);
        return 2;
      }
    }
    for (const auto& layers : config.layer_specs) parse_layer_spec(layers);
    if (config.view_size < 1 || config.view_size > kMaxViewSide || config.resolution < 1 ||
        config.resolution > kMaxDepthMapSide)
      throw InputError("--hm_size and --hm_res must be in [1, 16384]");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-bench: %s\n", e.what());
    return 2;
  }
  const Provenance prov = provenance();
  benchmark::AddCustomContext("heightmarch_commit", prov.commit);
  benchmark::AddCustomContext("heightmarch_cpu", prov.cpu);
  benchmark::AddCustomContext("heightmarch_compiler", prov.compiler);
  benchmark::AddCustomContext("heightmarch_best_isa", to_string(best_isa()));
  benchmark::AddCustomContext("heightmarch_view", "default " + std::to_string(config.view_size) + "x" +
                                                      std::to_string(config.view_size));
  benchmark::AddCustomContext("heightmarch_depth_map", std::to_string(config.resolution) + "x" +
                                                           std::to_string(config.resolution));
  bench::register_benchmarks(config);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
