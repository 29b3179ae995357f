// build/heightmarch-bench: Google Benchmark over the registries (techniques x layer specs x ISA
// x threads, the same as GLSL, POM-32's anchors: the sampler roofline, the compute ceiling, the
// naive port, its auto-vectorised form and its Highway form per ISA, and the exact reference) on the default view
// of each heightfield. Names come from benchmark_name(), as in a suite's bench.json; counters
// carry speed and accuracy. A configuration is checked against the scalar reference before it is
// timed: a wrong kernel never produces a number.
#include <benchmark/benchmark.h>
#include <tbb/info.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <optional>

#include "baselines/naive_port.hpp"
#include "experiment/measurement_session.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/tracer.hpp"
#include "io/atomic_file.hpp"
#include "io/provenance.hpp"

namespace {

using namespace heightmarch;

struct BenchOptions {
  int size = 1024;
  int res = 512;
  std::vector<std::string> heightfields = {"bricks", "terrain"};
  std::vector<std::string> layers = {"4", "8", "16", "32", "64", "8-32"};
  std::vector<int> threads;  // empty: 1 and all cores
  std::vector<std::string> isas;  // empty: every ISA the CPU runs
  double min_time = 0.2;
};

MeasurementSession& session() {
  static MeasurementSession s;
  return s;
}

void set_counters(benchmark::State& state, const Measurement& m) {
  const double iterations = double(state.iterations());
  state.SetItemsProcessed(std::int64_t(m.rays) * state.iterations());
  state.counters["rays_per_second"] = benchmark::Counter(double(m.rays) * iterations, benchmark::Counter::kIsRate);
  if (!m.samples_known) return;
  state.counters["samples_per_second"] = benchmark::Counter(double(m.samples) * iterations, benchmark::Counter::kIsRate);
  state.counters["samples_per_ray"] = m.rays ? double(m.samples) / double(m.rays) : 0.0;
  if (m.config.kind == RunKind::trace) state.counters["simd_utilization"] = m.simd_utilization;
  if (m.precompute_seconds) state.counters["precompute_seconds"] = *m.precompute_seconds;  // not in the rates
  if (!m.errors) return;
  for (const auto& [name, value] : error_counters(*m.errors)) state.counters[name] = value;
}

// Google Benchmark calls a benchmark again for each iteration-count estimate: the accuracy is
// measured (and checked) once per configuration.
void run_benchmark(benchmark::State& state, const Configuration& config) {
  static std::map<const Configuration*, Measurement> measured;
  auto it = measured.find(&config);
  if (it == measured.end()) it = measured.emplace(&config, session().measure(config)).first;
  const Measurement& m = it->second;
  if (!m.failure.empty()) return state.SkipWithError(m.failure.c_str());
  const ThreadLimit limit(config.threads);
  const std::function<double()> once = session().trace_once(config);
  once();  // warm-up: llvmpipe compiles the shader on its first draw
  // The trace's own time (for GLSL the worker's time of the draw, without the round trip to it).
  for (auto _ : state) state.SetIterationTime(once());
  set_counters(state, m);
}

std::vector<Configuration> bench_plan(const BenchOptions& o) {
  std::vector<int> threads = o.threads;
  if (threads.empty()) {
    threads = {1};
    if (tbb::info::default_concurrency() > 1) threads.push_back(tbb::info::default_concurrency());
  }
  std::vector<Isa> isas;
  for (const std::string& name : o.isas) isas.push_back(parse_isa(name, "--hm_isas"));
  if (isas.empty()) isas = supported_isas();
  std::vector<LayerSpec> layer_specs;
  for (const std::string& text : o.layers) layer_specs.push_back(parse_layer_spec(text));
  std::vector<Configuration> plan;
  for (const std::string& name : o.heightfields) {
    Configuration base;
    base.heightfield = parse_heightfield(name, o.res);
    base.view = parse_view("default", o.size, o.size);
    auto add = [&](RunKind kind, Technique technique, const LayerSpec& layers, Isa isa, int t) {
      Configuration c = base;
      c.kind = kind;
      c.params.technique = technique;
      c.params.layers = layers_for(technique, layers);
      c.isa = isa;
      c.threads = t;
      add_to_plan(plan, c);
    };
    for (const TechniqueInfo& t : techniques())
      for (const LayerSpec& layers : layer_specs)
        for (int n : threads) {
          for (Isa isa : isas) add(RunKind::trace, t.id, layers, isa, n);
          add(RunKind::glsl, t.id, layers, Isa::scalar, n);
        }
    for (int n : threads) {
      for (Isa isa : isas) {
        for (RunKind anchor : {RunKind::roofline, RunKind::ceiling, RunKind::autovec})
          add(anchor, Technique::pom, parse_layer_spec("32"), isa, n);
        if (highway_port_runs(isa)) add(RunKind::highway, Technique::pom, parse_layer_spec("32"), isa, n);
      }
      for (const char* layers : {"32", "8-32"}) add(RunKind::naive, Technique::pom, parse_layer_spec(layers), Isa::scalar, n);
      // The exact reference beside the techniques it measures (its float pass at the widest ISA asked for).
      add(RunKind::exact, Technique::pom, parse_layer_spec("1"), isas.back(), n);
    }
  }
  return plan;
}

int depth_map_side(const HeightfieldSource& source) { return source.builtin.empty() ? -1 : source.resolution; }

// Google Benchmark's file reporter, told apart from its stream's failure (a full disk): the file
// goes to a temporary that is renamed into place only when every byte was written.
template <class Base>
class CheckedReporter : public Base {
 public:
  bool failed() const { return failed_; }
  void Finalize() override {
    Base::Finalize();
    this->GetOutputStream().flush();
    failed_ = !this->GetOutputStream();
  }

 private:
  bool failed_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  BenchOptions o;
  CLI::App app("heightmarch-bench: Google Benchmark over heightmarch's techniques, ISAs and GLSL. Google Benchmark's own "
               "--benchmark_* flags are accepted too (--benchmark_filter, --benchmark_repetitions, --benchmark_out, ...).",
               "heightmarch-bench");
  app.allow_extras();
  app.set_help_flag("-h,--help", "this text, then Google Benchmark's flags");
  app.add_option("--hm_size", o.size, "view side in pixels")->check(CLI::Range(1, kMaxViewSide))->capture_default_str();
  app.add_option("--hm_res", o.res, "builtin depth map side")->check(CLI::Range(1, kMaxDepthMapSide))->capture_default_str();
  app.add_option("--hm_heightfields", o.heightfields, "builtin names or depth map files")->delimiter(',')->capture_default_str();
  app.add_option("--hm_layers", o.layers, "layer specs (N or A-B)")->delimiter(',')->capture_default_str();
  app.add_option("--hm_threads", o.threads, "thread counts (default: 1 and all cores)")->delimiter(',')->check(CLI::Range(1, 1024));
  app.add_option("--hm_isas", o.isas, isa_names() + " (default: every ISA the CPU runs)")->delimiter(',');
  app.add_option("--hm_min_time", o.min_time, "seconds per benchmark (Google Benchmark's --benchmark_min_time)")
      ->check(CLI::Range(0.0, 60.0))->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    std::fputs("\nGoogle Benchmark's flags:\n", stdout);
    char help[] = "--help";
    char* gbench_argv[] = {argv[0], help, nullptr};
    int gbench_argc = 2;
    benchmark::Initialize(&gbench_argc, gbench_argv);  // prints its usage and exits
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "heightmarch-bench: %s\n", e.what());
    return 2;
  }
  if (!std::isfinite(o.min_time)) {  // CLI11's range check lets NaN through
    std::fprintf(stderr, "heightmarch-bench: --hm_min_time: %g is not a finite number of seconds\n", o.min_time);
    return 2;
  }
  // Our flags are ours; whatever remains must be Google Benchmark's.
  std::vector<std::string> rest = app.remaining();
  bool has_min_time = false;
  for (const std::string& arg : rest) {
    if (arg.rfind("--benchmark_", 0) != 0) {
      std::fprintf(stderr, "heightmarch-bench: unknown option %s (see --help)\n", arg.c_str());
      return 2;
    }
    has_min_time = has_min_time || arg.rfind("--benchmark_min_time", 0) == 0;
  }
  // The minimum time goes through Google Benchmark's global flag, so names carry no min_time.
  if (!has_min_time) rest.push_back("--benchmark_min_time=" + std::to_string(o.min_time));
  // --benchmark_out=FILE is written to FILE.tmp-PID and renamed once whole (CheckedReporter).
  std::string out_path, out_format = "json";
  // The reporter writes into the atomic writer's temporary through /proc/self/fd: it never opens
  // a name in the directory itself.
  std::optional<AtomicFile> out_file;
  for (std::string& arg : rest) {
    if (arg.rfind("--benchmark_out=", 0) == 0) {
      out_path = arg.substr(std::string("--benchmark_out=").size());
      try {
        out_file.emplace(out_path);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "heightmarch-bench: %s\n", printable(e.what()).c_str());
        return 1;
      }
      arg = "--benchmark_out=/proc/self/fd/" + std::to_string(out_file->descriptor());
    } else if (arg.rfind("--benchmark_out_format=", 0) == 0) {
      out_format = arg.substr(std::string("--benchmark_out_format=").size());
    }
  }
  if (out_format != "json" && out_format != "console") {  // csv is deprecated in Google Benchmark
    std::fprintf(stderr, "heightmarch-bench: --benchmark_out_format=%s: json or console\n", out_format.c_str());
    return 2;
  }
  std::vector<char*> gbench_argv = {argv[0]};
  for (std::string& arg : rest) gbench_argv.push_back(arg.data());
  int gbench_argc = int(gbench_argv.size());
  gbench_argv.push_back(nullptr);
  std::vector<Configuration>* plan = nullptr;
  // Every depth map file named is read before any benchmark runs: a bad one is one line, exit 2.
  std::map<const Configuration*, std::pair<int, int>> sizes;
  try {
    static std::vector<Configuration> configurations = bench_plan(o);
    plan = &configurations;
    for (const Configuration& c : *plan) {
      int side = depth_map_side(c.heightfield);
      std::pair<int, int> size{side, side};
      if (side < 0) {  // a file: its size names the benchmark
        const DepthMap map = load_heightfield(c.heightfield);
        size = {map.width, map.height};
      }
      sizes[&c] = size;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&gbench_argc, gbench_argv.data());
  if (benchmark::ReportUnrecognizedArguments(gbench_argc, gbench_argv.data())) return 2;
  const Provenance prov = provenance();
  benchmark::AddCustomContext("heightmarch_commit", prov.commit);
  benchmark::AddCustomContext("heightmarch_cpu", prov.cpu);
  benchmark::AddCustomContext("heightmarch_compiler", prov.compiler);
  benchmark::AddCustomContext("heightmarch_build_type", prov.build_type);
  benchmark::AddCustomContext("heightmarch_best_isa", to_string(best_isa()));
  benchmark::AddCustomContext("heightmarch_error_measures", error_measure_names());
  benchmark::AddCustomContext("heightmarch_view", std::to_string(o.size) + "x" + std::to_string(o.size));
  benchmark::AddCustomContext("heightmarch_depth_map", std::to_string(o.res) + "x" + std::to_string(o.res));
  for (const Configuration& c : *plan) {
    const auto [width, height] = sizes.at(&c);
    benchmark::RegisterBenchmark(benchmark_name(c, width, height).c_str(),
                                 [&c](benchmark::State& state) { run_benchmark(state, c); })
        ->UseManualTime()
        ->MeasureProcessCPUTime()
        ->Unit(benchmark::kMillisecond);
  }
  if (out_path.empty()) {
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
  }
  CheckedReporter<benchmark::JSONReporter> json;
  CheckedReporter<benchmark::ConsoleReporter> console;
  const bool as_console = out_format == "console";
  benchmark::RunSpecifiedBenchmarks(nullptr, as_console ? static_cast<benchmark::BenchmarkReporter*>(&console) : &json);
  benchmark::Shutdown();
  const bool write_failed = as_console ? console.failed() : json.failed();
  std::string why = write_failed ? out_path + ": cannot write (a write failed; a full disk?)" : "";
  if (!write_failed) try {
      out_file->commit();
    } catch (const std::exception& e) {
      why = e.what();
    }
  if (why.empty()) return 0;
  std::fprintf(stderr, "heightmarch-bench: %s\n", printable(why).c_str());  // the temporary goes with out_file
  return 1;
}
