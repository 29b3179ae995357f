#include "bench_registry.hpp"

#include <benchmark/benchmark.h>
#include <tbb/info.h>

#include <functional>
#include <map>
#include <memory>
#include <mutex>

#include "heightmarch/claims_measurement.hpp"
#include "heightmarch/experiment.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "naive_port.hpp"

namespace heightmarch::bench {
namespace {

// A heightfield's depth map, default view and exact hits, built on first use.
struct BenchScene {
  Scene scene;
  HitBuffers exact;
};

class SceneCache {
 public:
  explicit SceneCache(const BenchConfig& config) : config_(config) {}

  const BenchScene& get(const std::string& heightfield) {
    std::lock_guard lock(mutex_);
    auto& slot = scenes_[heightfield];
    if (!slot) {
      slot = std::make_unique<BenchScene>();
      slot->scene = make_scene(heightfield, config_.resolution, 1, Convention::depth,
                               parse_view("default", config_.view_size, config_.view_size));
      slot->exact = exact_hits(slot->scene, TechniqueParams{});
    }
    return *slot;
  }

  // The scalar reference's hits for a configuration, computed once.
  const HitBuffers& reference(const std::string& heightfield, const TechniqueParams& params) {
    const BenchScene& s = get(heightfield);
    const std::string key = heightfield + "/" + to_string(params.technique) + "/" + to_string(params.layers);
    std::lock_guard lock(mutex_);
    auto& slot = references_[key];
    if (!slot) {
      slot = std::make_unique<HitBuffers>();
      Tracer(s.scene.map, params, Isa::scalar).run(s.scene.rays, *slot);
    }
    return *slot;
  }

 private:
  const BenchConfig& config_;
  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<BenchScene>> scenes_;
  std::map<std::string, std::unique_ptr<HitBuffers>> references_;
};

std::unique_ptr<SceneCache> cache;

// The first ray whose hit differs from the reference, or -1.
long long first_difference(const RayBatch& rays, const HitBuffers& a, const HitBuffers& b) {
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (a.samples[i] != b.samples[i] || a.u[i] != b.u[i] || a.v[i] != b.v[i] || a.depth[i] != b.depth[i] ||
        a.shadow[i] != b.shadow[i])
      return (long long)i;
  return -1;
}

void set_speed_counters(benchmark::State& state, std::size_t rays, std::uint64_t samples) {
  const double iterations = double(state.iterations());
  state.SetItemsProcessed(std::int64_t(rays) * state.iterations());
  state.counters["rays_per_second"] = benchmark::Counter(double(rays) * iterations, benchmark::Counter::kIsRate);
  state.counters["samples_per_second"] = benchmark::Counter(double(samples) * iterations, benchmark::Counter::kIsRate);
}

void set_error_counters(benchmark::State& state, const ErrorSummary& e) {
  state.counters["samples_per_ray"] = e.samples_per_ray;
  state.counters["uv_error_mean"] = e.mean;
  state.counters["uv_error_rms"] = e.rms;
  state.counters["uv_error_p50"] = e.p50;
  state.counters["uv_error_p95"] = e.p95;
  state.counters["uv_error_p99"] = e.p99;
  state.counters["uv_error_max"] = e.max;
  state.counters["wrong_surface_rate"] = e.wrong_surface_rate;
  state.counters["depth_error_mean"] = e.depth_error_mean;
  if (e.has_shadow) {
    state.counters["shadow_error_mean"] = e.shadow_error_mean;
    state.counters["shadow_mismatch_rate"] = e.shadow_mismatch_rate;
  }
}

// What a benchmark checks and measures before it times anything. Google Benchmark calls a
// benchmark function again for each iteration-count estimate: this runs once per benchmark.
struct Checked {
  std::string error;  // non-empty: the output differs from the reference, never timed
  ErrorSummary errors;
  std::uint64_t samples = 0;
  double simd_utilization = 1.0;
};

const Checked& checked_once(const std::string& key, const std::function<Checked()>& check) {
  static std::map<std::string, Checked> done;
  auto it = done.find(key);
  if (it == done.end()) it = done.emplace(key, check()).first;
  return it->second;
}

// Hits of the timed runs; benchmarks run one after another, so one buffer serves all.
HitBuffers& scratch_hits() {
  static HitBuffers hits;
  return hits;
}

void bm_trace(benchmark::State& state, const std::string& name, std::string heightfield, TechniqueParams params, Isa isa, int threads) {
  const BenchScene& s = cache->get(heightfield);
  const ThreadLimit limit(threads);
  const Tracer tracer(s.scene.map, params, isa);
  const Checked& c = checked_once(name, [&] {
    Checked checked;
    RunResult run;
    const TraceStats stats = tracer.run(s.scene.rays, run.hits);
    if (const long long i = first_difference(s.scene.rays, run.hits, cache->reference(heightfield, params)); i >= 0) {
      checked.error = "output differs from the scalar reference at ray " + std::to_string(i);
      return checked;
    }
    measure(s.scene, s.exact, params, run);
    checked.errors = run.errors;
    checked.samples = stats.samples;
    checked.simd_utilization = stats.simd_utilization();
    return checked;
  });
  if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
  for (auto _ : state) tracer.run(s.scene.rays, scratch_hits());
  set_speed_counters(state, s.scene.rays.ray_count, c.samples);
  set_error_counters(state, c.errors);
  state.counters["simd_utilization"] = c.simd_utilization;
}

void bm_sampler_roofline(benchmark::State& state, const std::string& name, std::string heightfield, int steps, Isa isa, int threads) {
  const BenchScene& s = cache->get(heightfield);
  TechniqueParams params;
  params.layers = {float(steps), float(steps)};
  const ThreadLimit limit(threads);
  const Tracer tracer(s.scene.map, params, isa);
  const Checked& c = checked_once(name, [&] {
    // Checked like a kernel: its sums and last positions must be the scalar roofline's.
    Checked checked;
    HitBuffers hits, reference;
    checked.samples = tracer.run_sampler_roofline(s.scene.rays, hits).samples;
    Tracer(s.scene.map, params, Isa::scalar).run_sampler_roofline(s.scene.rays, reference);
    if (first_difference(s.scene.rays, hits, reference) >= 0) checked.error = "roofline output differs from the scalar reference";
    return checked;
  });
  if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
  for (auto _ : state) tracer.run_sampler_roofline(s.scene.rays, scratch_hits());
  set_speed_counters(state, s.scene.rays.ray_count, c.samples);
}

void bm_naive_port(benchmark::State& state, const std::string& name, std::string heightfield, TechniqueParams params, int threads) {
  const BenchScene& s = cache->get(heightfield);
  const ThreadLimit limit(threads);
  auto trace = [&](HitBuffers& hits) {
    bench::naive_pom(s.scene.map, s.scene.rays, params.layers.min_layers, params.layers.max_layers, params.scale, hits);
  };
  const Checked& c = checked_once(name, [&] {
    Checked checked;
    const HitBuffers& reference = cache->reference(heightfield, params);
    RunResult run;
    trace(run.hits);
    // Its own texture() blends as glm::mix does and rounds differently: within 0.01 texel.
    for (std::size_t i = 0; i < s.scene.rays.size(); ++i) {
      const float d = uv_error_texels(run.hits.u[i], run.hits.v[i], reference.u[i], reference.v[i], s.scene.map.width,
                                      s.scene.map.height);
      if (!(d <= 1e-2f) && run.hits.samples[i] == reference.samples[i]) {
        checked.error = "naive port differs from the reference by " + std::to_string(d) + " texel";
        return checked;
      }
    }
    checked.samples = total_samples(s.scene.rays, run.hits);
    run.hits.depth = reference.depth;  // the port returns uv only
    measure(s.scene, s.exact, params, run);
    checked.errors = run.errors;
    return checked;
  });
  if (!c.error.empty()) return state.SkipWithError(c.error.c_str());
  for (auto _ : state) trace(scratch_hits());
  set_speed_counters(state, s.scene.rays.ray_count, c.samples);
  set_error_counters(state, c.errors);
}

// The GLSL run: draw + glFinish timed, the JIT-compiling first draw excluded, read-back outside.
void bm_glsl(benchmark::State& state, const std::string& name, std::string heightfield, TechniqueParams params, int threads) {
  const BenchScene& s = cache->get(heightfield);
  GlslRunner& runner = GlslRunner::instance(threads);
  runner.prepare(s.scene.map, params, s.scene.rays);
  runner.draw();
  const Checked& c = checked_once(name, [&] {
    Checked checked;
    RunResult run;
    runner.read(run.hits, run.samples_known);
    checked.samples = total_samples(s.scene.rays, run.hits);
    measure(s.scene, s.exact, params, run);
    checked.errors = run.errors;
    return checked;
  });
  for (auto _ : state) runner.draw();
  set_speed_counters(state, s.scene.rays.ray_count, c.samples);
  set_error_counters(state, c.errors);
}

}  // namespace

void register_benchmarks(const BenchConfig& input) {
  static BenchConfig config;
  config = input;
  if (config.threads.empty()) {
    config.threads = {1};
    if (tbb::info::default_concurrency() > 1) config.threads.push_back(tbb::info::default_concurrency());
  }
  if (config.isas.empty()) config.isas = supported_isas();
  if (config.glsl_threads <= 0) config.glsl_threads = config.threads.back();
  // Builtin names become "builtin:NAME"; anything else is a depth map file.
  for (std::string& heightfield : config.heightfields)
    if (heightfield.find_first_of("/.") == std::string::npos) heightfield = "builtin:" + heightfield;
  cache = std::make_unique<SceneCache>(config);
  const std::vector<std::string>& layer_specs = config.layer_specs;
  auto add = [](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark(name.c_str(), [name, fn](benchmark::State& st) { fn(st, name); })
        ->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(config.min_time);
  };
  for (const std::string& heightfield : config.heightfields)
    for (Technique technique : all_techniques()) {
      if (technique == Technique::exact) continue;
      const bool layered = technique != Technique::parallax && technique != Technique::parallax_limited;
      for (const std::string& layers : layered ? layer_specs : std::vector<std::string>{"1"})
        for (Isa isa : config.isas)
          for (int threads : config.threads) {
            TechniqueParams params;
            params.technique = technique;
            params.layers = parse_layer_spec(layers);
            const std::string name = "BM_Trace/heightfield:" + heightfield_label(heightfield) + "/technique:" + to_string(technique) +
                                     "/layers:" + layers + "/isa:" + to_string(isa) +
                                     "/threads:" + std::to_string(threads);
            add(name, [=](benchmark::State& st, const std::string& name) { bm_trace(st, name, heightfield, params, isa, threads); });
          }
    }
  // llvmpipe's thread count is fixed per process (LP_NUM_THREADS is read once): one count here.
  for (const std::string& heightfield : config.heightfields)
    for (Technique technique : all_techniques()) {
      if (technique == Technique::exact) continue;
      const bool layered = technique != Technique::parallax && technique != Technique::parallax_limited;
      for (const std::string& layers : layered ? layer_specs : std::vector<std::string>{"1"}) {
        TechniqueParams params;
        params.technique = technique;
        params.layers = parse_layer_spec(layers);
        const int threads = config.glsl_threads;
        add("BM_GLSL/heightfield:" + heightfield_label(heightfield) + "/technique:" + to_string(technique) +
                "/layers:" + layers + "/isa:glsl/threads:" + std::to_string(threads),
            [=](benchmark::State& st, const std::string& name) { bm_glsl(st, name, heightfield, params, threads); });
      }
    }
  for (const std::string& heightfield : config.heightfields)
    for (Isa isa : config.isas)
      for (int threads : config.threads)
        add("BM_SamplerRoofline/heightfield:" + heightfield_label(heightfield) + "/layers:32/isa:" + to_string(isa) +
                "/threads:" + std::to_string(threads),
            [=](benchmark::State& st, const std::string& name) { bm_sampler_roofline(st, name, heightfield, 32, isa, threads); });
  for (const std::string& heightfield : config.heightfields)
    for (const char* layers : {"32", "8-32"})
      for (int threads : config.threads) {
        TechniqueParams params;
        params.technique = Technique::pom;
        params.layers = parse_layer_spec(layers);
        add("BM_NaivePort/heightfield:" + heightfield_label(heightfield) + "/technique:pom/layers:" + std::string(layers) +
                "/isa:scalar-naive/threads:" + std::to_string(threads),
            [=](benchmark::State& st, const std::string& name) { bm_naive_port(st, name, heightfield, params, threads); });
      }
}

}  // namespace heightmarch::bench
