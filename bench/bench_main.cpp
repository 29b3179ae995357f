// build/heightmarch-bench: Google Benchmark over the suite's typed plan (suite_plan.hpp), filtered
// as the suite filters it, timed rows only: the technique x layers matrix and the same as GLSL,
// the searches at every ISA and thread count, POM-32's anchors (the sampler roofline, the compute
// ceiling, the naive port, its auto-vectorised and its Highway forms per ISA, the hand-written
// kernel's structure on Highway's ops per ISA), the exact reference and the calibration loop that
// scripts/compare takes the machine's speed from, on a window of each heightfield (--hm_views:
// the single default view unless asked). Names come from benchmark_name(), as in a suite's
// bench.json; counters carry speed and accuracy. A configuration is checked against the scalar
// reference before it is timed: a wrong kernel never produces a number.
#include <benchmark/benchmark.h>
#include <tbb/info.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <regex>
#include <set>

#include "cli/typed_option.hpp"
#include "experiment/measurement_session.hpp"
#include "experiment/suite_plan.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/tracer.hpp"
#include "io/atomic_file.hpp"
#include "io/provenance.hpp"
#include "util/repeats.hpp"

namespace {

using namespace heightmarch;

struct BenchOptions {
  std::string size = "1024";  // the default view: N (N x N) or WxH pixels
  // The window (--views of the tool): single by default, so that scripts/regress and bisect time
  // a build of today and one from before view sets on the same rays.
  ViewSet views = ViewSet::single();
  int res = 512;
  std::vector<std::string> heightfields = {"bricks", "terrain"};
  PlanFilters filters;                                  // empty lists: the suite's default
  std::vector<int> threads;                             // empty: 1 and all cores
  std::vector<std::string> map_filters = {"bilinear"};  // how the depth map is read: the plan under each
  std::vector<std::string> gl;  // GL paths of the GLSL benchmarks; empty: the worker's default
  std::string gl_device;        // EGL's device for them; empty: EGL's first
  double min_time = 0.2;
  bool dry_run = false;
};

// The parts heightmarch-bench times unless told: the suite's timed parts but the claims' rows.
const std::vector<std::string> kDefaultParts = {"matrix", "isa",   "glsl",       "roofline",
                                                "naive",  "exact", "calibration"};

MeasurementSession& session() {
  static MeasurementSession s;
  return s;
}

void set_counters(benchmark::State& state, const Measurement& m) {
  const double iterations = double(state.iterations());
  state.SetItemsProcessed(std::int64_t(m.rays) * state.iterations());
  state.counters["rays_per_second"] =
      benchmark::Counter(double(m.rays) * iterations, benchmark::Counter::kIsRate);
  // A GLSL draw's two clocks, the median seconds of the timed draws (the manual time is one of them:
  // GlDrawTime::seconds()).
  if (!m.gl_wall_seconds.empty()) state.counters["gl_wall_seconds"] = spread_of(m.gl_wall_seconds).median;
  if (!m.gl_timer_seconds.empty()) state.counters["gl_timer_seconds"] = spread_of(m.gl_timer_seconds).median;
  if (!m.samples_known) return;
  state.counters["samples_per_second"] =
      benchmark::Counter(double(m.samples) * iterations, benchmark::Counter::kIsRate);
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
  const std::function<TraceTime()> once = session().trace_once(config);
  once();  // warm-up: llvmpipe compiles the shader on its first draw
  // The trace's own time (for GLSL the worker's time of the draw, without the round trip to it);
  // a GLSL draw's two clocks are kept for the counters.
  Measurement timed = m;
  for (auto _ : state) {
    const TraceTime time = once();
    state.SetIterationTime(time.seconds);
    if (!time.gl) continue;
    timed.gl_wall_seconds.push_back(time.gl->wall_seconds);
    if (time.gl->timer_seconds) timed.gl_timer_seconds.push_back(*time.gl->timer_seconds);
  }
  set_counters(state, timed);
}

// --hm_size: N or WxH, each side in [1, kMaxViewSide]; InputError otherwise.
void view_size(const std::string& text, int& width, int& height) {
  const std::size_t x = text.find('x');
  const std::string w = text.substr(0, x), h = x == std::string::npos ? w : text.substr(x + 1);
  const auto side = [&](const std::string& digits, int& out) {
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), out);
    return error == std::errc() && end == digits.data() + digits.size() && out >= 1 && out <= kMaxViewSide;
  };
  if (!side(w, width) || !side(h, height))
    throw InputError("--hm_size " + printable(text) + ": not N or WxH with sides in [1, " +
                     std::to_string(kMaxViewSide) + "]");
}

// The suite's plan at the options' sizes, heightfields, threads and filters, with the Highway
// port: its timed configurations.
std::vector<Configuration> bench_plan(const BenchOptions& o) {
  refuse_repeats(o.threads, "--hm_threads", [](int t) { return std::to_string(t); });
  std::vector<int> threads = o.threads;
  if (threads.empty()) {
    threads = {1};
    if (tbb::info::default_concurrency() > 1) threads.push_back(tbb::info::default_concurrency());
  }
  std::sort(threads.begin(), threads.end());
  threads.erase(std::unique(threads.begin(), threads.end()), threads.end());
  PlanSettings settings = suite_settings(false, threads.back());
  settings.thread_counts = threads;
  int width = 0, height = 0;
  view_size(o.size, width, height);
  settings.window = seen_as(default_view(width, height), o.views);
  settings.heightfields.clear();
  for (const std::string& name : o.heightfields)
    settings.heightfields.push_back(parse_heightfield(name, o.res));
  refuse_repeats(settings.heightfields, "--hm_heightfields",
                 [](const HeightfieldSource& h) { return h.describe(); });
  give_unique_labels(settings.heightfields);
  settings.large_maps = false;
  settings.highway = true;
  settings.matrix_everywhere = true;
  std::vector<Filter> map_filters;
  for (const std::string& name : o.map_filters) map_filters.push_back(parse_filter(name));
  refuse_repeats(map_filters, "--hm_filters", [](Filter f) { return to_string(f); });
  settings.filter = map_filters.front();
  PlanFilters filters = o.filters;
  filters.option_prefix = "--hm_";
  if (filters.parts.empty()) filters.parts = kDefaultParts;
  apply(filters, settings);
  // Each GL path asked for is a GLSL benchmark of its own (gl:PATH in its name), side by side: the
  // first path's plan whole, the others' GLSL rows.
  const std::vector<std::string> paths = o.gl.empty() ? std::vector<std::string>{""} : o.gl;
  std::vector<GlTarget> targets;
  for (const std::string& path : paths) {
    targets.push_back(parse_gl_target(path, o.gl_device));
    targets.back().path = resolved(targets.back()).path;
  }
  refuse_repeats(targets, "--hm_gl",
                 [](const GlTarget& t) { return t.path ? to_string(*t.path) : std::string("the default"); });
  std::vector<Configuration> plan;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    settings.gl = targets[i];
    for (const Configuration& c : benchmark_plan(settings)) {
      if (i != 0 && c.kind != RunKind::glsl) continue;
      add_to_plan(plan, c);
      // Under each other filter asked for, the kinds that take one, side by side (adjacent in the plan).
      for (std::size_t j = 1; takes_filter(c.kind) && j < map_filters.size(); ++j) {
        Configuration twin = c;
        twin.params.filter = map_filters[j];
        add_to_plan(plan, twin);
      }
    }
  }
  return plan;
}

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

// Google Benchmark's flags (1.7), each checked before any is passed on: Google Benchmark takes a
// negative repetition count to an abort in vector::reserve, a NaN minimum time to a hang, and an
// unknown format or a broken regular expression to a message and exit 0.
enum class FlagKind { boolean, text, filter, seconds, count, format, out_format, color, context, unit };
const std::map<std::string, FlagKind>& benchmark_flags() {
  static const std::map<std::string, FlagKind> flags = {
      {"list_tests", FlagKind::boolean},
      {"filter", FlagKind::filter},
      {"min_time", FlagKind::seconds},
      {"min_warmup_time", FlagKind::seconds},
      {"repetitions", FlagKind::count},
      {"enable_random_interleaving", FlagKind::boolean},
      {"report_aggregates_only", FlagKind::boolean},
      {"display_aggregates_only", FlagKind::boolean},
      {"format", FlagKind::format},
      {"out", FlagKind::text},
      {"out_format", FlagKind::out_format},
      {"color", FlagKind::color},
      {"counters_tabular", FlagKind::boolean},
      {"perf_counters", FlagKind::text},
      {"context", FlagKind::context},
      {"time_unit", FlagKind::unit},
  };
  return flags;
}

// Throws InputError naming the flag unless it is one of Google Benchmark's, with a value it
// takes as meant, and given once.
void check_benchmark_flags(const std::vector<std::string>& args) {
  std::set<std::string> seen;
  for (const std::string& arg : args) {
    const std::size_t eq = arg.find('=');
    const std::string name =
        arg.substr(std::strlen("--benchmark_"),
                   eq == std::string::npos ? std::string::npos : eq - std::strlen("--benchmark_"));
    const bool bare = eq == std::string::npos;
    const std::string value = bare ? "" : arg.substr(eq + 1);
    const auto flag = benchmark_flags().find(name);
    const std::string shown = "--benchmark_" + name;
    if (flag == benchmark_flags().end()) throw InputError("unknown option " + arg + " (see --help)");
    if (!seen.insert(name).second) throw InputError(shown + " is given twice");
    const auto refuse = [&](const std::string& what) { throw InputError(shown + "=" + value + ": " + what); };
    // Google Benchmark reads a boolean and a colour in any case, the other words as written.
    const auto one_of = [&](std::initializer_list<const char*> names, bool any_case = false) {
      std::string text = value;
      if (any_case)
        for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
      return std::any_of(names.begin(), names.end(), [&](const char* n) { return text == n; });
    };
    if (bare && flag->second != FlagKind::boolean) refuse("takes a value");
    switch (flag->second) {
      case FlagKind::boolean:
        if (!bare && !one_of({"true", "false", "yes", "no", "on", "off", "1", "0"}, true))
          refuse("true or false");
        break;
      case FlagKind::text:
        if (value.empty()) refuse("empty");
        break;
      case FlagKind::filter:
        try {
          std::regex(value.rfind('-', 0) == 0 ? value.substr(1) : value, std::regex::extended);
        } catch (const std::regex_error&) {
          refuse("not a regular expression");
        }
        break;
      case FlagKind::seconds: {
        double seconds = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), seconds);
        if (ec != std::errc() || end != value.data() + value.size() || !(seconds >= 0 && seconds <= 3600) ||
            (name == "min_time" && seconds == 0))
          refuse(name == "min_time" ? "seconds in (0, 3600]" : "seconds in [0, 3600]");
        break;
      }
      case FlagKind::count: {
        int count = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), count);
        if (ec != std::errc() || end != value.data() + value.size() || count < 1 || count > 1000)
          refuse("a whole number in 1..1000");
        break;
      }
      case FlagKind::format:
      case FlagKind::out_format:  // csv is deprecated in Google Benchmark
        if (!one_of({"json", "console"})) refuse("json or console");
        break;
      case FlagKind::color:
        if (!one_of({"auto", "true", "false", "yes", "no", "on", "off", "1", "0"}, true))
          refuse("auto, true or false");
        break;
      case FlagKind::context:
        for (std::size_t at = 0; at <= value.size();) {
          const std::size_t comma = std::min(value.find(',', at), value.size());
          const std::string pair = value.substr(at, comma - at);
          if (pair.find('=') == 0 || pair.find('=') == std::string::npos)
            refuse("KEY=VALUE pairs, comma-separated");
          at = comma + 1;
        }
        break;
      case FlagKind::unit:
        if (!one_of({"ns", "us", "ms", "s"})) refuse("ns, us, ms or s");
        break;
    }
  }
}

}  // namespace

// The whole run, its errors caught by main() below.
int run(int argc, char** argv) {
  BenchOptions o;
  CLI::App app(
      "heightmarch-bench: Google Benchmark over heightmarch's techniques, ISAs and GLSL. Google Benchmark's "
      "own "
      "--benchmark_* flags are accepted too (--benchmark_filter, --benchmark_repetitions, --benchmark_out, "
      "...).",
      "heightmarch-bench");
  app.allow_extras();
  app.set_help_flag("-h,--help", "this text, then Google Benchmark's flags");
  app.add_option("--hm_size", o.size, "the view: N (N x N) or WxH pixels")->capture_default_str();
  cli::add_typed_option(app, "--hm_views", o.views, parse_view_set,
                        "the window: single (default), around, tutorial[:N] (frames of --hm_size), or a "
                        "camera-pose CSV (docs/measures.md#view-sets)");
  app.add_option("--hm_res", o.res, "builtin depth map side")
      ->check(CLI::Range(1, kMaxDepthMapSide))
      ->capture_default_str();
  app.add_option("--hm_heightfields", o.heightfields, "builtin names or depth map files")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--hm_techniques", o.filters.techniques, technique_names() + " (default: all)")
      ->delimiter(',');
  app.add_option("--hm_layers", o.filters.layers,
                 "layer specs, N or A-B (default: the suite's, 4, 8, 10, 16, 32, 64, 8-32)")
      ->delimiter(',');
  app.add_option("--hm_threads", o.threads, "thread counts (default: 1 and all cores)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1024));
  app.add_option("--hm_isas", o.filters.isas, isa_names() + " (default: every ISA the CPU runs)")
      ->delimiter(',');
  app.add_option(
         "--hm_filters", o.map_filters,
         "bilinear, trilinear or both: the kernels, their anchors and GLSL under each (names of trilinear "
         "ones end in /filter:trilinear)")
      ->delimiter(',')
      ->check(CLI::IsMember(filter_names()))
      ->capture_default_str();
  app.add_option("--hm_gl", o.gl,
                 "GL paths of the GLSL benchmarks, " + gl_path_names() +
                     ", comma-separated: each its own benchmarks, side by side (default: osmesa where built, "
                     "else egl)")
      ->delimiter(',');
  app.add_option("--hm_gl_device", o.gl_device,
                 "EGL device of the GLSL benchmarks: software, or an index or name from `heightmarch glsl "
                 "--list-devices` (default: EGL's first)");
  std::string parts;
  for (const std::string& name : part_names()) parts += (parts.empty() ? "" : ", ") + name;
  app.add_option(
         "--hm_parts", o.filters.parts,
         "the parts of the suite's plan to time: " + parts + " (default: " +
             [] {
               std::string names;
               for (const std::string& name : kDefaultParts) names += (names.empty() ? "" : ",") + name;
               return names;
             }() +
             ")")
      ->delimiter(',');
  app.add_flag("--hm_dry_run", o.dry_run,
               "read and check every input as a run would, list the configurations it would time, as "
               "suite --dry-run does, and time nothing");
  app.add_option("--hm_min_time", o.min_time,
                 "seconds per benchmark (Google Benchmark's --benchmark_min_time)")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
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
    std::fprintf(stderr, "heightmarch-bench: %s\n", error_line(e.what()).c_str());
    return 2;
  }
  if (!std::isfinite(o.min_time)) {  // CLI11's range check lets NaN through
    std::fprintf(stderr, "heightmarch-bench: --hm_min_time: %g is not a finite number of seconds\n",
                 o.min_time);
    return 2;
  }
  // Our flags are ours; whatever remains must be Google Benchmark's, each checked before it sees it.
  std::vector<std::string> rest = app.remaining();
  bool has_min_time = false;
  for (const std::string& arg : rest) {
    if (arg.rfind("--benchmark_", 0) != 0) throw InputError("unknown option " + arg + " (see --help)");
    has_min_time = has_min_time || arg.rfind("--benchmark_min_time", 0) == 0;
  }
  check_benchmark_flags(rest);
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
        std::fprintf(stderr, "heightmarch-bench: %s\n", error_line(e.what()).c_str());
        return 1;
      }
      arg = "--benchmark_out=/proc/self/fd/" + std::to_string(out_file->descriptor());
    } else if (arg.rfind("--benchmark_out_format=", 0) == 0) {
      out_format = arg.substr(std::string("--benchmark_out_format=").size());
    }
  }
  std::vector<char*> gbench_argv = {argv[0]};
  for (std::string& arg : rest) gbench_argv.push_back(arg.data());
  int gbench_argc = int(gbench_argv.size());
  gbench_argv.push_back(nullptr);
  std::vector<Configuration>* plan = nullptr;
  // Every input the plan reads (depth maps, views, GL targets) is read and checked once, into the
  // session, before any benchmark runs, as the suite does, and by --hm_dry_run too: a bad one is
  // one line, exit 2. A file's size names its benchmarks.
  std::map<const Configuration*, std::pair<int, int>> sizes;
  try {
    static std::vector<Configuration> configurations = bench_plan(o);
    plan = &configurations;
    session().check_inputs(*plan);
    if (o.dry_run) {
      for (const Configuration& c : *plan) std::printf("%s\n", plan_line(c).c_str());
      std::printf("%zu configurations\n", plan->size());
      return 0;
    }
    for (const Configuration& c : *plan) {
      const HeightfieldSource& source = c.heightfield;
      sizes[&c] = source.builtin.empty() ? std::pair<int, int>{session().depth_map(source).width,
                                                               session().depth_map(source).height}
                                         : std::pair<int, int>{source.resolution, source.resolution};
    }
  } catch (const InputError& e) {
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
  benchmark::AddCustomContext("heightmarch_view",
                              plan->empty() ? "none" : benchmark_view(plan->front().view));
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
  benchmark::RunSpecifiedBenchmarks(
      nullptr, as_console ? static_cast<benchmark::BenchmarkReporter*>(&console) : &json);
  benchmark::Shutdown();
  const bool write_failed = as_console ? console.failed() : json.failed();
  std::string why = write_failed ? out_path + ": cannot write (a write failed; a full disk?)" : "";
  if (!write_failed) try {
      out_file->commit();
    } catch (const std::exception& e) {
      why = e.what();
    }
  if (why.empty()) return 0;
  std::fprintf(stderr, "heightmarch-bench: %s\n",
               error_line(why).c_str());  // the temporary goes with out_file
  return 1;
}

// Every way the run can stop is one line and a status, as heightmarch's: input it cannot use (a
// views file, a flag; also one a benchmark meets only once it runs) exit 2, a result it cannot
// write 1, memory 3.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const InputError& e) {
    std::fprintf(stderr, "heightmarch-bench: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "heightmarch-bench: out of memory\n");
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-bench: %s\n", error_line(e.what()).c_str());
    return 1;
  }
}
