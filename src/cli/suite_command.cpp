// heightmarch suite: the main job. Runs the benchmark matrix (CPU per ISA and GLSL), the error
// sweeps over view angles, the gallery and the claims, then writes the report into
// results/<date>-<commit>/ (or --out DIR) and points results/latest at it.
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/suite_plan.hpp"
#include "heightmarch/claims_measurement.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/experiment.hpp"
#include "io/atomic_file.hpp"
#include "io/images.hpp"
#include "io/json_writer.hpp"
#include "io/provenance.hpp"

namespace heightmarch::cli {

namespace fs = std::filesystem;

SuitePlan make_suite_plan(bool quick, const std::string& extra_heightmaps) {
  SuitePlan plan;
  plan.quick = quick;
  if (quick) {
    plan.heightfields = {"builtin:bricks", "builtin:terrain"};
    plan.layer_specs = {"8", "32", "8-32"};
    plan.resolution = 256;
    plan.bench_view_size = 256;
    plan.bench_min_time = 0.02;
    plan.sweep_size = 48;
    plan.gallery_width = 256;
    plan.gallery_height = 192;
    plan.claims_view_size = 128;
    plan.claims_sweep_size = 48;
  } else {
    plan.heightfields = {"builtin:bricks", "builtin:toybox", "builtin:terrain", "builtin:waves", "builtin:spikes"};
    plan.layer_specs = {"4", "8", "10", "16", "32", "64", "8-32"};
  }
  std::stringstream extra(extra_heightmaps);
  for (std::string path; std::getline(extra, path, ',');)
    if (!path.empty()) {
      if (!fs::exists(path)) throw InputError(path + ": no such depth map file");
      plan.heightfields.push_back(path);
    }
  plan.sweep_heightfields = quick ? std::vector<std::string>{plan.heightfields.front()} : plan.heightfields;
  return plan;
}

namespace {

// Progress on a terminal (what runs, how far, time left); a line per stage when quiet (CI).
class Progress {
 public:
  Progress() : interactive_(isatty(2) && !std::getenv("CI")), start_(std::chrono::steady_clock::now()) {}

  void stage(const std::string& name) {
    finish_line();
    stage_ = name;
    stage_start_ = std::chrono::steady_clock::now();
    std::fprintf(stderr, "suite: %s (%.0f s elapsed)\n", name.c_str(), elapsed(start_));
  }

  void step(std::size_t done, std::size_t total, const std::string& what) {
    if (!interactive_ || total == 0) return;
    const double seconds = elapsed(stage_start_);
    const double left = done ? seconds / double(done) * double(total - done) : 0.0;
    std::fprintf(stderr, "\r\033[K  [%zu/%zu] %.0f s left  %s", done, total, left, what.substr(0, 90).c_str());
    std::fflush(stderr);
    pending_line_ = true;
  }

  void finish_line() {
    if (pending_line_) std::fprintf(stderr, "\n");
    pending_line_ = false;
  }

  double total_seconds() const { return elapsed(start_); }

 private:
  static double elapsed(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
  }
  bool interactive_;
  bool pending_line_ = false;
  std::string stage_;
  std::chrono::steady_clock::time_point start_, stage_start_;
};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string executable_dir() { return fs::read_symlink("/proc/self/exe").parent_path().string(); }

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

// Runs heightmarch-bench with the filter into out/<name>, showing progress.
void run_bench_process(const std::string& arguments, const std::string& filter, const std::string& out,
                       const std::string& name, Progress& progress) {
  const std::string bench = executable_dir() + "/heightmarch-bench";
  const std::string common = shell_quote(bench) + " --benchmark_filter=" + shell_quote(filter) + arguments;
  // Count first, so progress can say how far it is.
  std::size_t total = 0;
  if (FILE* list = popen((common + " --benchmark_list_tests=true").c_str(), "r")) {
    char line[1024];
    while (std::fgets(line, sizeof line, list)) total += std::strncmp(line, "BM_", 3) == 0;
    pclose(list);
  }
  const std::string part = out + "/" + name + ".part";
  FILE* run = popen((common + " --benchmark_out=" + shell_quote(part) + " --benchmark_out_format=json 2>&1").c_str(), "r");
  if (!run) throw std::runtime_error("cannot start " + bench);
  std::size_t done = 0;
  char line[4096];
  std::string log;
  while (std::fgets(line, sizeof line, run)) {
    log += line;
    if (std::strncmp(line, "BM_", 3) != 0) continue;
    progress.step(++done, total, std::string(line, std::strcspn(line, " ")));
  }
  const int status = pclose(run);
  progress.finish_line();
  if (status != 0) throw std::runtime_error("heightmarch-bench failed:\n" + log.substr(log.size() > 2000 ? log.size() - 2000 : 0));
  fs::rename(part, out + "/" + name);
  write_file_atomically(out + "/" + name + ".log", log);
}

// The benchmark matrix: every technique x layer spec at the best ISA and all threads, POM-32 at
// every ISA and thread count, GLSL, the sampler roofline and the naive port. llvmpipe's thread
// count is fixed per process, so GLSL at one thread runs in a second process.
void run_benchmarks(const SuitePlan& plan, const std::string& out, Isa isa, int threads, bool glsl,
                    Progress& progress) {
  const std::string layers = "(1|" + join(plan.layer_specs, "|") + ")";  // 1: the parallax techniques
  std::vector<std::string> heightfields;
  for (const auto& hf : plan.heightfields) heightfields.push_back(hf.rfind("builtin:", 0) == 0 ? hf.substr(8) : hf);
  const std::string arguments = " --hm_heightfields=" + shell_quote(join(heightfields, ",")) +
                                " --hm_layers=" + shell_quote(join(plan.layer_specs, ",")) +
                                " --hm_size=" + std::to_string(plan.bench_view_size) +
                                " --hm_res=" + std::to_string(plan.resolution) +
                                " --hm_threads=1," + std::to_string(threads) +
                                " --hm_min_time=" + std::to_string(plan.bench_min_time);
  std::string filter = "BM_Trace/.*/layers:" + layers + "/isa:" + to_string(isa) + "/threads:" + std::to_string(threads) +
                       "/|BM_Trace/.*/technique:pom/layers:32/|BM_SamplerRoofline/|BM_NaivePort/";
  if (glsl) filter += "|BM_GLSL/.*/layers:" + layers + "/";
  run_bench_process(arguments + " --hm_glsl_threads=" + std::to_string(threads), filter, out, "bench.json", progress);
  if (glsl && threads > 1)
    run_bench_process(arguments + " --hm_glsl_threads=1", "BM_GLSL/.*/layers:(8|32|8-32)/", out,
                      "bench-glsl-1thread.json", progress);
}

// Error against view angle: sweep views from 0 to 85 degrees, every technique at a few layer specs.
void write_sweeps(const SuitePlan& plan, const std::string& out, Isa isa, Progress& progress) {
  std::string csv = "heightfield,technique,layers,theta,phi,rays,uv_error_mean,uv_error_p95,uv_error_max,wrong_surface_rate,samples_per_ray\n";
  const std::vector<std::string> layer_specs = {"8", "32", "8-32"};
  const std::size_t angles = 18;
  const std::size_t total = plan.sweep_heightfields.size() * angles;
  std::size_t done = 0;
  for (const std::string& spec : plan.sweep_heightfields) {
    Scene scene = make_scene(spec, plan.resolution, 1, Convention::depth, parse_view("sweep:0", plan.sweep_size, plan.sweep_size));
    for (std::size_t a = 0; a < angles; ++a) {
      const double theta = 5.0 * double(a);
      const ViewSpec view = parse_view("sweep:" + std::to_string(theta), plan.sweep_size, plan.sweep_size);
      set_view(scene, view);
      const HitBuffers exact = exact_hits(scene, TechniqueParams{});
      for (Technique technique : all_techniques()) {
        if (technique == Technique::exact || technique == Technique::shadow) continue;
        const bool layered = technique != Technique::parallax && technique != Technique::parallax_limited;
        for (const std::string& layers : layered ? layer_specs : std::vector<std::string>{"1"}) {
          TechniqueParams params;
          params.technique = technique;
          params.layers = parse_layer_spec(layers);
          const RunResult run = run_cpu(scene, exact, params, isa, 0, 0.0);
          char row[512];
          std::snprintf(row, sizeof row, "%s,%s,%s,%g,%g,%zu,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                        heightfield_label(spec).c_str(), to_string(technique).c_str(), layers.c_str(), theta,
                        double(view.phi_degrees), run.errors.rays, run.errors.mean, run.errors.p95, run.errors.max,
                        run.errors.wrong_surface_rate, run.errors.samples_per_ray);
          csv += row;
        }
      }
      progress.step(++done, total, heightfield_label(spec) + " at " + std::to_string(int(theta)) + " degrees");
    }
  }
  progress.finish_line();
  write_file_atomically(out + "/sweep.csv", csv);
}

// The tutorial's comparison collage, with numbers: render and error map per technique.
void write_gallery(const SuitePlan& plan, const std::string& out, Isa isa, Progress& progress) {
  const std::string spec = plan.heightfields.front();
  const std::string label = heightfield_label(spec);
  const Scene scene = make_scene(spec, plan.resolution, 1, Convention::depth,
                                 parse_view("default", plan.gallery_width, plan.gallery_height));
  fs::create_directories(out + "/gallery");
  JsonWriter json;
  json.begin_object().value("view", scene.view).value("heightfield", label).begin_array("entries");
  const std::vector<std::pair<Technique, std::string>> entries = {
      {Technique::exact, "-"},        {Technique::parallax, "1"}, {Technique::parallax_limited, "1"},
      {Technique::steep, "10"},       {Technique::steep_limited, "10"}, {Technique::relief, "10"},
      {Technique::pom, "10"},         {Technique::pom, "32"},     {Technique::shadow, "32"}};
  TechniqueParams exact_params;
  const HitBuffers exact = exact_hits(scene, exact_params);
  std::size_t done = 0;
  for (const auto& [technique, layers] : entries) {
    TechniqueParams params;
    params.technique = technique;
    if (layers != "-") params.layers = parse_layer_spec(layers);
    const RunResult run = run_cpu(scene, exact, params, isa, 0, 0.0);
    const std::string stem = "gallery/" + label + "-" + to_string(technique) + (layers == "-" ? "" : "-" + layers);
    const std::string dir = out + "/" + stem;
    write_run_outputs(dir, scene, params, run, exact);
    fs::rename(dir + "/render.png", out + "/" + stem + "-render.png");
    fs::rename(dir + "/error.png", out + "/" + stem + "-error.png");
    fs::remove_all(dir);
    json.begin_object().value("technique", to_string(technique)).value("layers", layers)
        .value("render", stem + "-render.png").value("error", stem + "-error.png")
        .value("uv_error_mean", run.errors.mean).value("uv_error_p95", run.errors.p95)
        .value("wrong_surface_rate", run.errors.wrong_surface_rate).value("rays_per_second", run.rays_per_second())
        .end_object();
    progress.step(++done, entries.size(), to_string(technique));
  }
  progress.finish_line();
  json.end_array().end_object();
  write_file_atomically(out + "/gallery.json", json.str() + "\n");
}

void write_machine(const std::string& out, const SuitePlan& plan, Isa isa, int threads) {
  const Provenance p = provenance();
  JsonWriter json;
  json.begin_object().value("commit", p.commit).value("cpu", p.cpu).value("cores", p.cores).value("compiler", p.compiler)
      .value("date", p.date).value("best_isa", to_string(isa)).value("threads", threads).value("quick", plan.quick)
      .end_object();
  write_file_atomically(out + "/machine.json", json.str() + "\n");
}

}  // namespace

int suite_command(const std::vector<std::string>& args) {
  const std::vector<OptionSpec> specs = {
      {"quick", false, "a smoke run in about two minutes: two heightfields, small views"},
      {"out", true, "run directory (default results/<date>-<commit>, and results/latest points at it)"},
      {"heightmap", true, "extra depth map files, comma-separated, measured beside the builtins"},
      {"threads", true, "worker threads (default: all cores)"},
      {"no-glsl", false, "skip the GLSL (OSMesa) benchmarks"},
      {"help", false, "this text"},
  };
  const Options options(args, specs);
  if (options.has("help")) {
    std::printf("usage: heightmarch suite [options]\n%s", usage(specs).c_str());
    return 0;
  }
  const SuitePlan plan = make_suite_plan(options.has("quick"), options.text("heightmap", ""));
  const Isa isa = best_isa();
  const ThreadLimit limit(thread_count(options));
  const Provenance p = provenance();
  const bool default_out = !options.has("out");
  const std::string run_name = p.date.substr(0, 10) + "-" + p.commit + (plan.quick ? "-quick" : "");
  const std::string out = default_out ? "results/" + run_name : options.text("out", "");
  fs::create_directories(out);
  // Present until the run completes, listing what finished: an interrupted run says so.
  const std::string marker = out + "/INCOMPLETE";
  std::string finished = "This run did not complete. Finished stages:\n";
  write_file_atomically(marker, finished);
  auto done = [&](const std::string& stage) {
    finished += "- " + stage + "\n";
    write_file_atomically(marker, finished);
  };
  Progress progress;
  write_machine(out, plan, isa, limit.threads());
  progress.stage("benchmarks (CPU per ISA" + std::string(options.has("no-glsl") ? "" : ", GLSL") + ")");
  run_benchmarks(plan, out, isa, limit.threads(), !options.has("no-glsl"), progress);
  done("benchmarks: bench.json");
  progress.stage("error against view angle");
  write_sweeps(plan, out, isa, progress);
  done("sweeps: sweep.csv");
  progress.stage("gallery");
  write_gallery(plan, out, isa, progress);
  done("gallery: gallery/, gallery.json");
  progress.stage("claims");
  write_claims(out, plan, isa, limit.threads());
  done("claims: claims.md, claims.json");
  progress.stage("report");
  std::string report = "/usr/bin/python3 " + shell_quote(std::string(HEIGHTMARCH_SOURCE_DIR) + "/scripts/report.py") + " " +
                       shell_quote(out);
  if (default_out) report += " --history results/history.csv";
  if (std::system(report.c_str()) != 0) throw std::runtime_error("scripts/report.py failed for " + out);
  fs::remove(marker);
  if (default_out) {
    std::error_code ec;
    fs::remove("results/latest", ec);
    fs::create_directory_symlink(run_name, "results/latest");
  }
  std::fprintf(stderr, "suite: done in %.0f s: %s/report.md\n", progress.total_seconds(), out.c_str());
  return 0;
}

}  // namespace heightmarch::cli
