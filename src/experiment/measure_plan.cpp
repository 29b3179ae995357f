// The measurement pass: the one place that joins tracing (CPU kernels, GLSL, the naive port),
// the exact reference and the error measures.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "baselines/naive_port.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/exact.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/measurement.hpp"
#include "heightmarch/trace.hpp"

namespace heightmarch {

std::vector<double> Measurement::rays_per_second() const {
  std::vector<double> rates;
  for (double s : seconds) rates.push_back(s > 0 ? double(rays) / s : 0.0);
  return rates;
}

std::vector<double> Measurement::samples_per_second() const {
  std::vector<double> rates;
  for (double s : seconds) rates.push_back(s > 0 ? double(samples) / s : 0.0);
  return rates;
}

Spread spread_of(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return {median, values.front(), values.back()};
}

void add_to_plan(std::vector<Configuration>& plan, const Configuration& config) {
  for (Configuration& c : plan)
    if (c.same_measurement(config)) {
      c.purposes |= config.purposes;
      c.timed = c.timed || config.timed;
      return;
    }
  plan.push_back(config);
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// CPU time of the whole machine and of this process, in clock ticks, to tell how much of the
// machine other processes used while we timed.
struct CpuTicks {
  double machine_busy = 0, self = 0;
};

CpuTicks read_cpu_ticks() {
  CpuTicks ticks;
  std::ifstream stat("/proc/stat");
  std::string cpu;
  double user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
  if (stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal)
    ticks.machine_busy = user + nice + system + irq + softirq + steal;
  std::ifstream self("/proc/self/stat");
  std::string line;
  std::getline(self, line);
  // Fields after the command name (which may hold spaces) start at the last ')'.
  const auto close = line.rfind(')');
  if (close != std::string::npos) {
    std::istringstream rest(line.substr(close + 2));
    std::string field;
    double utime = 0, stime = 0;
    for (int i = 3; i <= 15 && rest >> field; ++i) {
      if (i == 14) utime = std::atof(field.c_str());
      if (i == 15) stime = std::atof(field.c_str());
    }
    ticks.self = utime + stime;
  }
  return ticks;
}

void read_load_average(double (&load)[3]) {
  std::ifstream in("/proc/loadavg");
  in >> load[0] >> load[1] >> load[2];
}

// Keys of what configurations of one scene share.
std::string params_key(const TechniqueParams& p, bool with_technique) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%d/%g/%g/%d/%a/%d/%d/%a/%a/%a", with_technique ? int(p.technique) : -1,
                p.layers.min_layers, p.layers.max_layers, p.refine_steps(), p.scale, int(p.wrap), int(p.discard),
                p.light[0], p.light[1], p.light[2]);
  return buf;
}

long long first_difference(const RayBatch& rays, const HitBuffers& a, const HitBuffers& b) {
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (a.samples[i] != b.samples[i] || a.u[i] != b.u[i] || a.v[i] != b.v[i] || a.depth[i] != b.depth[i] ||
        a.shadow[i] != b.shadow[i] || a.discarded[i] != b.discarded[i])
      return (long long)i;
  return -1;
}

// What a Tracer runs for a trace, roofline or ceiling configuration.
TraceStats run_tracer(const Tracer& tracer, RunKind kind, const RayBatch& rays, HitBuffers& hits) {
  switch (kind) {
    case RunKind::roofline: return tracer.run_sampler_roofline(rays, hits);
    case RunKind::ceiling: return tracer.run_compute_ceiling(rays, hits);
    default: return tracer.run(rays, hits);
  }
}

// Everything the configurations of one heightfield and view share.
class SceneRun {
 public:
  SceneRun(const DepthMap& map, const ViewSpec& view) : map(map), rays(make_view_rays(view)) {}

  const HitBuffers& exact(const TechniqueParams& params) {
    const LightVisibility visibility = visibility_for(params.technique);
    auto& slot = exact_[params_key(params, false) + (visibility == LightVisibility::compute ? "/visibility" : "")];
    if (!slot) slot = std::make_unique<HitBuffers>(exact_hits(map, rays, params, visibility));
    return *slot;
  }

  // The scalar reference of a technique (trace), of the roofline or of the ceiling, computed once.
  const HitBuffers& reference(const TechniqueParams& params, RunKind kind) {
    auto& slot = references_[params_key(params, kind == RunKind::trace) + "/" + to_string(kind)];
    if (!slot) {
      slot = std::make_unique<HitBuffers>();
      run_tracer(Tracer(map, params, Isa::scalar), kind, rays, *slot);
    }
    return *slot;
  }

  const DepthMap& map;
  const RayBatch rays;
  HitBuffers scratch;  // hits of timed runs: one buffer, so timings see no page faults

 private:
  std::map<std::string, std::unique_ptr<HitBuffers>> exact_, references_;
};

TechniqueParams roofline_params(const TechniqueParams& params) {
  TechniqueParams p = params;
  p.layers = {32.0f, 32.0f};
  return p;
}

// A brought-in loop that never ends is cut off by llvmpipe (or optimised away) and leaves
// garbage, NaN or coordinates far beyond any texture (at 1e6 a float has no texel precision
// left): no figure is made from it.
void check_finite(const Configuration& c, const RayBatch& rays, const HitBuffers& hits) {
  constexpr float kAbsurd = 1e6f;
  std::size_t not_finite = 0, first = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    const bool finite = std::isfinite(hits.u[i]) && std::isfinite(hits.v[i]) && std::isfinite(hits.depth[i]);
    if (!finite || std::fabs(hits.u[i]) > kAbsurd || std::fabs(hits.v[i]) > kAbsurd)
      if (not_finite++ == 0) first = i;
  }
  if (not_finite)
    throw InputError((c.shader_path().empty() ? "GLSL " + to_string(c.params.technique) : c.shader_path()) +
                     ": returned a non-finite uv or depth (or a uv beyond 1e6) for " + std::to_string(not_finite) + " of " +
                     std::to_string(rays.ray_count) + " rays (first: T = " + std::to_string(rays.tx[first]) + "," +
                     std::to_string(rays.ty[first]) + "); an endless loop ends this way in llvmpipe");
}

// The naive port (and its auto-vectorised form) blends as glm::mix does and rounds differently:
// within 0.01 texel of the reference wherever it took the same samples.
std::string check_naive(const Configuration& c, const RayBatch& rays, const HitBuffers& hits, const HitBuffers& reference,
                        const DepthMap& map) {
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const float d = uv_error_texels(hits.u[i], hits.v[i], reference.u[i], reference.v[i], map.width, map.height);
    if (!(d <= 1e-2f) && hits.samples[i] == reference.samples[i])
      return (c.kind == RunKind::autovec ? c.backend() + " auto-vectorised port" : std::string("naive port")) +
             " differs from the reference by " + std::to_string(d) + " texel at ray " + std::to_string(i);
  }
  return "";
}

// The naive port, or its auto-vectorised form for the configuration's ISA.
void run_port(const Configuration& c, const DepthMap& map, const RayBatch& rays, HitBuffers& hits) {
  const LayerSpec& l = c.params.layers;
  if (c.kind == RunKind::autovec)
    autovec_pom(map, rays, l.min_layers, l.max_layers, c.params.scale, c.isa, hits);
  else
    naive_pom(map, rays, l.min_layers, l.max_layers, c.params.scale, hits);
}

}  // namespace

struct MeasurementSession::State {
  std::vector<std::pair<HeightfieldSource, std::unique_ptr<DepthMap>>> maps;
  std::vector<std::pair<Configuration, std::unique_ptr<SceneRun>>> scenes;  // by heightfield and view
  std::map<const Configuration*, std::unique_ptr<Tracer>> tracers;
  std::map<const Configuration*, std::unique_ptr<ExactReference>> exact_references;

  const DepthMap& depth_map(const HeightfieldSource& source) {
    for (auto& [s, map] : maps)
      if (s == source) return *map;
    maps.emplace_back(source, std::make_unique<DepthMap>(load_heightfield(source)));
    return *maps.back().second;
  }

  SceneRun& scene(const Configuration& c) {
    for (auto& [key, scene] : scenes)
      if (key.heightfield == c.heightfield && key.view == c.view) return *scene;
    scenes.emplace_back(c, std::make_unique<SceneRun>(depth_map(c.heightfield), c.view));
    return *scenes.back().second;
  }

  // One Tracer per configuration, kept for its timed runs (keyed by the caller's object).
  const Tracer& tracer(SceneRun& scene, const Configuration& c) {
    auto& slot = tracers[&c];
    if (!slot)
      slot = std::make_unique<Tracer>(scene.map, c.kind == RunKind::roofline ? roofline_params(c.params) : c.params, c.isa);
    return *slot;
  }

  // Likewise the exact reference, its float pass at the configuration's ISA.
  const ExactReference& exact_reference(SceneRun& scene, const Configuration& c) {
    auto& slot = exact_references[&c];
    if (!slot) slot = std::make_unique<ExactReference>(scene.map, c.params, c.isa);
    return *slot;
  }
};

MeasurementSession::MeasurementSession() : state_(std::make_unique<State>()) {}
MeasurementSession::~MeasurementSession() = default;

void MeasurementSession::forget_scenes() {
  state_->tracers.clear();
  state_->exact_references.clear();
  state_->scenes.clear();
}

Measurement MeasurementSession::measure(const Configuration& c, int id,
                                        const std::function<void(const TracedRow&)>& on_traced) {
  Measurement row;
  row.config = c;
  row.id = id;
  SceneRun& scene = state_->scene(c);
  row.depth_map_width = scene.map.width;
  row.depth_map_height = scene.map.height;
  row.rays = scene.rays.ray_count;
  const HitBuffers& exact = scene.exact(c.params);
  HitBuffers hits;
  // What a tracer precomputes (the cone map) is built before the row's thread limit, in parallel.
  const bool traces = c.kind == RunKind::trace || c.kind == RunKind::roofline || c.kind == RunKind::ceiling;
  const Tracer* tracer = traces ? &state_->tracer(scene, c) : nullptr;
  if (tracer && tracer->cone_map()) row.cone_map_seconds = tracer->cone_map()->build_seconds;
  const ThreadLimit limit(c.threads);
  switch (c.kind) {
    case RunKind::trace: {
      const TraceStats stats = tracer->run(scene.rays, hits);
      row.simd_utilization = stats.simd_utilization();
      if (c.isa != Isa::scalar)
        if (const long long i = first_difference(scene.rays, hits, scene.reference(c.params, RunKind::trace)); i >= 0)
          row.failure = "output differs from the scalar reference at ray " + std::to_string(i);
      break;
    }
    case RunKind::roofline:
    case RunKind::ceiling: {
      run_tracer(*tracer, c.kind, scene.rays, hits);
      if (c.isa != Isa::scalar && first_difference(scene.rays, hits, scene.reference(tracer->params(), c.kind)) >= 0)
        row.failure = to_string(c.kind) + " output differs from the scalar reference";
      break;
    }
    case RunKind::glsl: {
      GlslRunner& runner = GlslRunner::instance(c.threads);
      runner.prepare(scene.map, c.params, scene.rays, c.shader_path());
      runner.draw();
      runner.read(hits, row.samples_known);
      row.samples_known = row.samples_known && c.shader_path().empty();
      check_finite(c, scene.rays, hits);
      if (!c.shader_path().empty()) {  // a loop llvmpipe cut off may leave different garbage each draw
        HitBuffers again;
        bool known = false;
        runner.draw();
        runner.read(again, known);
        if (const long long i = first_difference(scene.rays, hits, again); i >= 0)
          throw InputError(c.shader_path() + ": returned different hits on two draws of the same rays (first at ray " +
                           std::to_string(i) + "): not deterministic, as a non-finite uv or an endless loop cut off by llvmpipe");
      }
      break;
    }
    case RunKind::naive:
    case RunKind::autovec: {
      run_port(c, scene.map, scene.rays, hits);
      const HitBuffers& reference = scene.reference(c.params, RunKind::trace);
      row.failure = check_naive(c, scene.rays, hits, reference, scene.map);
      hits.depth = reference.depth;  // the port returns uv only
      break;
    }
    case RunKind::exact: hits = exact; break;
  }
  row.samples = total_samples(scene.rays, hits);
  // The roofline returns sums, the ceiling hits on a flat depth 1: neither has an accuracy.
  if (!row.failure.empty() || c.kind == RunKind::roofline || c.kind == RunKind::ceiling) return row;
  std::vector<float> uv_error;
  ErrorSummary errors = summarize_errors(scene.rays, hits, exact, scene.map.width, scene.map.height,
                                         c.has_technique() && c.params.technique == Technique::shadow, &uv_error);
  if (c.has_technique() && info(c.params.technique).layered)
    errors.within_one_layer_step =
        share_within_one_layer_step(scene.rays, hits, uv_error, c.params, scene.map.width, scene.map.height);
  row.errors = errors;
  if (on_traced) on_traced(TracedRow{row, scene.map, scene.rays, hits, exact, uv_error});
  return row;
}

std::function<double()> MeasurementSession::trace_once(const Configuration& c) {
  SceneRun& scene = state_->scene(c);
  auto timed = [](auto trace) {
    return [trace] {
      const Clock::time_point start = Clock::now();
      trace();
      return seconds_since(start);
    };
  };
  switch (c.kind) {
    case RunKind::trace:
    case RunKind::roofline:
    case RunKind::ceiling: {
      const Tracer& t = state_->tracer(scene, c);
      return timed([&t, &scene, kind = c.kind] { run_tracer(t, kind, scene.rays, scene.scratch); });
    }
    case RunKind::glsl: {
      GlslRunner& runner = GlslRunner::instance(c.threads);
      runner.prepare(scene.map, c.params, scene.rays, c.shader_path());
      return [&runner] { return runner.draw(); };
    }
    case RunKind::naive:
    case RunKind::autovec: return timed([&scene, c] { run_port(c, scene.map, scene.rays, scene.scratch); });
    case RunKind::exact: {
      const ExactReference& r = state_->exact_reference(scene, c);
      return timed([&r, &scene, c] { r.run(scene.rays, visibility_for(c.params.technique), scene.scratch); });
    }
  }
  return [] { return 0.0; };
}

namespace {

class PlanRunner {
 public:
  PlanRunner(const std::vector<Configuration>& plan, const MeasureOptions& options)
      : plan_(plan), options_(options) {
    for (const Configuration& c : plan) total_steps_ += 1 + (c.timed ? std::size_t(options.repetitions) : 0);
  }

  MeasuredPlan run() {
    MeasuredPlan result;
    result.repetitions = options_.repetitions;
    result.min_seconds = options_.min_seconds;
    read_load_average(result.load.before);
    result.rows.resize(plan_.size());
    // Scenes in first-seen order: every configuration on the same heightfield and view.
    std::vector<std::vector<std::size_t>> scenes;
    for (std::size_t i = 0; i < plan_.size(); ++i) {
      auto it = std::find_if(scenes.begin(), scenes.end(), [&](const std::vector<std::size_t>& s) {
        return plan_[s.front()].heightfield == plan_[i].heightfield && plan_[s.front()].view == plan_[i].view;
      });
      if (it == scenes.end()) scenes.push_back({i});
      else it->push_back(i);
    }
    for (const auto& members : scenes) run_scene(members, result.rows);
    read_load_average(result.load.after);
    finish_load(result.load);
    return result;
  }

 private:
  void step(const std::string& what) {
    if (options_.progress) options_.progress(what, ++done_steps_, total_steps_);
  }

  void run_scene(const std::vector<std::size_t>& members, std::vector<Measurement>& rows) {
    for (std::size_t i : members) {
      rows[i] = session_.measure(plan_[i], int(i), options_.on_traced);
      step(describe_row(rows[i]));
    }
    std::vector<std::size_t> timed;
    for (std::size_t i : members)
      if (plan_[i].timed && rows[i].failure.empty()) timed.push_back(i);
    for (int round = 0; round < options_.repetitions; ++round)
      for (std::size_t i : timed) {
        rows[i].seconds.push_back(time_repetition(plan_[i]));
        step(describe_row(rows[i]) + " (round " + std::to_string(round + 1) + ")");
      }
    session_.forget_scenes();
  }

  static std::string describe_row(const Measurement& m) {
    const Configuration& c = m.config;
    std::string what = c.heightfield.label() + " " + to_string(c.kind);
    if (c.has_technique() || c.shader) what += " " + c.label() + "-" + to_string(c.params.layers);
    return what + " " + c.backend() + " x" + std::to_string(c.threads) + " " + describe(c.view);
  }

  // One repetition: a warm-up trace, then traces until min_seconds have passed; the mean time of one.
  double time_repetition(const Configuration& c) {
    const ThreadLimit limit(c.threads);
    const std::function<double()> once = session_.trace_once(c);
    once();  // warm-up: caches, TBB's workers, llvmpipe's JIT after a prepare
    const bool cpu = c.kind != RunKind::glsl;
    const CpuTicks ticks_before = cpu ? read_cpu_ticks() : CpuTicks{};
    const Clock::time_point start = Clock::now();
    int runs = 0;
    double traced = 0, elapsed = 0;
    constexpr int kMaxRuns = 100000;
    do {
      traced += once();
      ++runs;
      elapsed = seconds_since(start);
    } while (elapsed < options_.min_seconds && runs < kMaxRuns);
    if (cpu) {
      const CpuTicks ticks_after = read_cpu_ticks();
      other_ticks_ += std::max(0.0, (ticks_after.machine_busy - ticks_before.machine_busy) -
                                        (ticks_after.self - ticks_before.self));
      timed_seconds_ += elapsed;
    }
    return traced / runs;
  }

  void finish_load(MachineLoad& load) const {
    const double ticks_per_second = double(sysconf(_SC_CLK_TCK));
    const double cores = std::max(1u, std::thread::hardware_concurrency());
    load.other_cpu_share = timed_seconds_ > 0 ? other_ticks_ / ticks_per_second / (timed_seconds_ * cores) : 0.0;
    char buf[160];
    if (load.other_cpu_share > 0.10) {
      std::snprintf(buf, sizeof buf, "other processes used %.0f%% of the machine's CPU time while CPU work was timed",
                    100 * load.other_cpu_share);
      load.busy_reasons.push_back(buf);
    }
    if (load.before[0] > 0.5 * cores) {
      std::snprintf(buf, sizeof buf, "the 1-minute load average was %.2f on %g cores before the run", load.before[0], cores);
      load.busy_reasons.push_back(buf);
    }
    load.busy = !load.busy_reasons.empty();
  }

  const std::vector<Configuration>& plan_;
  const MeasureOptions& options_;
  MeasurementSession session_;
  std::size_t total_steps_ = 0, done_steps_ = 0;
  double other_ticks_ = 0, timed_seconds_ = 0;
};

}  // namespace

MeasuredPlan measure_plan(const std::vector<Configuration>& plan, const MeasureOptions& options) {
  if (options.repetitions < 1 || options.repetitions > 1000)
    throw InputError("repetitions " + std::to_string(options.repetitions) + " outside [1, 1000]");
  if (!(options.min_seconds >= 0.0 && options.min_seconds <= 60.0))
    throw InputError("time per repetition outside [0, 60] s");
  return PlanRunner(plan, options).run();
}

}  // namespace heightmarch
