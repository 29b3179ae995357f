// heightmarch glsl: the technique as GLSL in OSMesa (llvmpipe) on the same rays as the CPU;
// --compare runs the CPU kernels beside it and reports conformance and the speed ratio.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/metrics.hpp"

namespace heightmarch::cli {

RunResult run_glsl(const Scene& scene, const HitBuffers& exact, const TechniqueParams& params, int threads,
                   const std::string& shader_path, double min_seconds, GlslRunner*& runner_out) {
  GlslRunner& runner = GlslRunner::instance(threads);
  runner_out = &runner;
  runner.prepare(scene.map, params, scene.rays, shader_path);
  runner.draw();  // the first draw JIT-compiles the shader: not timed
  RunResult run;
  run.backend = "glsl";
  run.threads = runner.threads();
  run.seconds = median_seconds([&] { runner.draw(); }, min_seconds, run.repetitions);
  runner.read(run.hits, run.samples_known);
  run.stats.samples = total_samples(scene.rays, run.hits);
  std::size_t not_finite = 0, first = 0;
  for (std::size_t i = 0; i < scene.rays.size(); ++i) {
    if (scene.rays.is_padding(i)) continue;
    if (!std::isfinite(run.hits.u[i]) || !std::isfinite(run.hits.v[i]) || !std::isfinite(run.hits.depth[i]))
      if (not_finite++ == 0) first = i;
  }
  // A brought-in loop that never ends is cut off by llvmpipe (or optimised away) and leaves
  // garbage: no figure is made from it.
  if (not_finite)
    throw InputError((shader_path.empty() ? std::string("GLSL ") + to_string(params.technique) : shader_path) +
                     ": returned a non-finite uv or depth for " + std::to_string(not_finite) + " of " +
                     std::to_string(scene.rays.ray_count) + " rays (first: T = " + std::to_string(scene.rays.tx[first]) +
                     "," + std::to_string(scene.rays.ty[first]) + "); an endless loop ends this way in llvmpipe");
  measure(scene, exact, params, run);
  return run;
}

int glsl_command(const std::vector<std::string>& args) {
  std::vector<OptionSpec> specs = trace_option_specs();
  specs.push_back({"shader", true, "GLSL file defining vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)"});
  specs.push_back({"compare", false, "also run the CPU kernels (best ISA) and report conformance and speed"});
  specs.push_back({"help", false, "this text"});
  const Options options(args, specs);
  if (options.has("help")) {
    std::printf("usage: heightmarch glsl [options]\n%s", usage(specs).c_str());
    return 0;
  }
  const TechniqueParams params = technique_params(options);
  const std::string shader = options.text("shader", "");
  const Scene scene = load_scene(options);
  const ThreadLimit limit(thread_count(options));
  const HitBuffers exact = exact_hits(scene, params);
  GlslRunner* runner = nullptr;
  const RunResult run = run_glsl(scene, exact, params, limit.threads(), shader, 0.3, runner);
  if (options.has("json")) {
    std::fputs(metrics_json(scene, params, run).c_str(), stdout);
  } else {
    std::printf("GLSL on %s, %s\n", runner->renderer().c_str(), runner->version().c_str());
    if (!shader.empty()) std::printf("brought-in shader %s (samples unknown)\n", shader.c_str());
    std::fputs(summary_text(scene, params, run).c_str(), stdout);
  }
  if (options.has("compare")) {
    const Isa isa = select_isa("");
    const RunResult cpu = run_cpu(scene, exact, params, isa, limit.threads(), 0.3);
    std::size_t same_samples = 0, measured = 0;
    std::vector<float> differences;
    for (std::size_t i = 0; i < scene.rays.size(); ++i) {
      if (scene.rays.is_padding(i)) continue;
      ++measured;
      same_samples += run.hits.samples[i] == cpu.hits.samples[i];
      differences.push_back(uv_error_texels(run.hits.u[i], run.hits.v[i], cpu.hits.u[i], cpu.hits.v[i],
                                            scene.map.width, scene.map.height));
    }
    std::sort(differences.begin(), differences.end());
    const double p99 = differences.empty() ? 0.0 : differences[std::min(differences.size() - 1, differences.size() * 99 / 100)];
    std::printf("conformance with the CPU (%s): identical sample counts %s, uv difference p99 %.3g max %.3g texels\n",
                isa == Isa::scalar ? "scalar" : to_string(isa).c_str(),
                run.samples_known ? (std::to_string(100.0 * double(same_samples) / double(measured)).substr(0, 6) + "%").c_str()
                                  : "unknown (brought-in shader)",
                p99, differences.empty() ? 0.0 : double(differences.back()));
    std::printf("speed at %d thread%s: CPU %.2f Mrays/s, GLSL %.2f Mrays/s, CPU/GLSL %.1fx\n", limit.threads(),
                limit.threads() == 1 ? "" : "s", cpu.rays_per_second() / 1e6, run.rays_per_second() / 1e6,
                cpu.rays_per_second() / run.rays_per_second());
  }
  if (const auto out = options.get("out")) write_run_outputs(*out, scene, params, run, exact);
  return 0;
}

}  // namespace heightmarch::cli
