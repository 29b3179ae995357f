#include "heightmarch/experiment.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "io/atomic_file.hpp"
#include "io/images.hpp"
#include "io/json_writer.hpp"
#include "io/provenance.hpp"

namespace heightmarch {

double RunResult::rays_per_second() const { return seconds > 0 ? double(errors.rays + errors.discarded) / seconds : 0.0; }
double RunResult::samples_per_second() const { return seconds > 0 ? double(stats.samples) / seconds : 0.0; }

Scene make_scene(const std::string& heightfield, int resolution, std::uint64_t seed, Convention convention,
                 const ViewSpec& view, int tile_size) {
  Scene scene;
  scene.heightfield = heightfield;
  scene.map = load_heightfield(heightfield, resolution, seed, convention);
  set_view(scene, view, tile_size);
  return scene;
}

void set_view(Scene& scene, const ViewSpec& view, int tile_size) {
  scene.rays = make_view_rays(view, tile_size);
  scene.view = describe(view);
  scene.rays_from_file = false;
}

double median_seconds(const std::function<void()>& once, double min_seconds, int& repetitions) {
  std::vector<double> times;
  double total = 0.0;
  while (times.empty() || (total < min_seconds && times.size() < 50)) {
    const auto start = std::chrono::steady_clock::now();
    once();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    total += times.back();
  }
  std::sort(times.begin(), times.end());
  repetitions = int(times.size());
  return times[times.size() / 2];
}

HitBuffers exact_hits(const Scene& scene, const TechniqueParams& params) {
  TechniqueParams exact_params = params;
  exact_params.technique = Technique::exact;
  HitBuffers hits;
  Tracer(scene.map, exact_params, Isa::scalar).run(scene.rays, hits);
  return hits;
}

void measure(const Scene& scene, const HitBuffers& exact, const TechniqueParams& params, RunResult& run) {
  run.errors = summarize_errors(scene.rays, run.hits, exact, scene.map.width, scene.map.height,
                                params.technique == Technique::shadow, &run.uv_error);
}

RunResult run_cpu(const Scene& scene, const HitBuffers& exact, const TechniqueParams& params, Isa isa,
                  int threads, double min_seconds) {
  RunResult run;
  run.backend = params.technique == Technique::exact ? "scalar-double" : to_string(isa);
  run.threads = threads;
  const Tracer tracer(scene.map, params, isa);
  run.seconds = median_seconds([&] { run.stats = tracer.run(scene.rays, run.hits); }, min_seconds, run.repetitions);
  measure(scene, exact, params, run);
  return run;
}

std::string metrics_json(const Scene& scene, const TechniqueParams& params, const RunResult& run) {
  const Provenance prov = provenance();
  const ErrorSummary& e = run.errors;
  JsonWriter json;
  json.begin_object()
      .value("technique", to_string(params.technique))
      .value("layers", to_string(params.layers))
      .value("refine", params.refine_steps)
      .value("isa", run.backend)
      .value("threads", run.threads)
      .value("width", scene.rays.image_width)
      .value("height", scene.rays.image_height)
      .value("rays", e.rays + e.discarded)
      .value("rays_per_second", run.rays_per_second())
      .value("samples_per_second", run.samples_per_second())
      .value("samples_per_ray", e.samples_per_ray)
      .value("simd_utilization", run.stats.simd_utilization())
      .begin_object("uv_error_texels")
      .value("mean", e.mean)
      .value("rms", e.rms)
      .value("p50", e.p50)
      .value("p95", e.p95)
      .value("p99", e.p99)
      .value("max", e.max)
      .end_object()
      .value("wrong_surface_rate", e.wrong_surface_rate)
      .value("depth_error_mean", e.depth_error_mean)
      .value("discarded", e.discarded);
  if (e.has_shadow)
    json.value("shadow_error_mean", e.shadow_error_mean).value("shadow_mismatch_rate", e.shadow_mismatch_rate);
  json.value("heightfield", scene.heightfield)
      .value("depth_map_width", scene.map.width)
      .value("depth_map_height", scene.map.height)
      .value("view", scene.view)
      .value("scale", double(params.scale))
      .value("wrap", params.wrap == Wrap::repeat ? "repeat" : "clamp")
      .value("discard", params.discard)
      .value("seconds", run.seconds)
      .value("repetitions", run.repetitions)
      .begin_object("provenance")
      .value("commit", prov.commit)
      .value("cpu", prov.cpu)
      .value("cores", prov.cores)
      .value("compiler", prov.compiler)
      .value("date", prov.date)
      .end_object()
      .end_object();
  return json.str() + "\n";
}

std::string summary_text(const Scene& scene, const TechniqueParams& params, const RunResult& run) {
  const ErrorSummary& e = run.errors;
  const std::string simd_use = run.stats.packet_samples
                                   ? ", SIMD use " + std::to_string(int(100.0 * run.stats.simd_utilization() + 0.5)) + "%"
                                   : "";
  char buf[1024];
  int n = std::snprintf(
      buf, sizeof buf,
      "%s layers %s on %s (%dx%d depth map), %s: %zu rays\n"
      "  %s, %d thread%s: %.2f Mrays/s, %.1f Msamples/s, %.2f samples/ray%s\n"
      "  uv error (texels): mean %.4f  rms %.4f  p50 %.4f  p95 %.4f  p99 %.4f  max %.4f\n"
      "  wrong surface %.2f%%, depth error mean %.5f, discarded %zu\n",
      to_string(params.technique).c_str(), to_string(params.layers).c_str(), scene.heightfield.c_str(),
      scene.map.width, scene.map.height, scene.view.c_str(), e.rays + e.discarded, run.backend.c_str(),
      run.threads, run.threads == 1 ? "" : "s", run.rays_per_second() / 1e6, run.samples_per_second() / 1e6,
      e.samples_per_ray, simd_use.c_str(), e.mean, e.rms, e.p50, e.p95, e.p99, e.max,
      100.0 * e.wrong_surface_rate, e.depth_error_mean, e.discarded);
  std::string text(buf, std::size_t(std::min(n, int(sizeof buf) - 1)));
  if (e.has_shadow) {
    std::snprintf(buf, sizeof buf, "  shadow: factor vs exact visibility mean |diff| %.4f, mismatch %.2f%%\n",
                  e.shadow_error_mean, 100.0 * e.shadow_mismatch_rate);
    text += buf;
  }
  return text;
}

void write_run_outputs(const std::string& dir, const Scene& scene, const TechniqueParams& params,
                       const RunResult& run, const HitBuffers& exact) {
  std::filesystem::create_directories(dir);
  const int w = scene.rays.image_width, h = scene.rays.image_height;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  // Scatter the batch (tile order) back to pixels; pixels without a ray stay -1 in hits.exr.
  std::vector<float> exr(pixels * 4, -1.0f), error(pixels, 0.0f), u(pixels, 0.0f), v(pixels, 0.0f),
      shadow(pixels, 1.0f);
  std::vector<std::uint8_t> has_ray(pixels, 0);
  const HitBuffers& hits = run.hits;
  for (std::size_t i = 0; i < scene.rays.size(); ++i) {
    if (scene.rays.is_padding(i)) continue;
    const std::size_t p = scene.rays.origin[i];
    exr[4 * p + 0] = hits.u[i];
    exr[4 * p + 1] = hits.v[i];
    exr[4 * p + 2] = hits.depth[i];
    exr[4 * p + 3] = float(hits.samples[i]);
    error[p] = run.uv_error[i];
    u[p] = hits.u[i];
    v[p] = hits.v[i];
    shadow[p] = params.technique == Technique::shadow ? hits.shadow[i] : 1.0f;
    has_ray[p] = !hits.discarded[i];
  }
  write_exr(dir + "/hits.exr", w, h, {"u", "v", "depth", "samples"}, exr);
  int heat_height = 0;
  const std::vector<std::uint8_t> heat = error_heat_map(error, has_ray, w, h, heat_height);
  write_png_rgb8(dir + "/error.png", w, heat_height, heat);
  write_png_rgb8(dir + "/render.png", w, h,
                 shade_render(scene.map, params.wrap, params.scale, u, v, shadow, has_ray, w, h, params.light));
  write_file_atomically(dir + "/metrics.json", metrics_json(scene, params, run));
  if (!scene.rays_from_file) return;
  std::string csv = "tx,ty,vx,vy,vz,u,v,depth,samples,exact_u,exact_v,exact_depth,uv_error_texels\n";
  std::vector<std::size_t> by_row(scene.rays.ray_count);
  for (std::size_t i = 0; i < scene.rays.size(); ++i)
    if (!scene.rays.is_padding(i)) by_row[scene.rays.origin[i]] = i;
  char line[512];
  for (std::size_t i : by_row) {
    const RayBatch& r = scene.rays;
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%s,%.9g,%.9g,%.9g,%.9g\n", r.tx[i],
                  r.ty[i], r.vx[i], r.vy[i], r.vz[i], hits.u[i], hits.v[i], hits.depth[i],
                  run.samples_known ? std::to_string(hits.samples[i]).c_str() : "", exact.u[i], exact.v[i],
                  exact.depth[i], run.uv_error[i]);
    csv += line;
  }
  write_file_atomically(dir + "/rays.csv", csv);
}

}  // namespace heightmarch
