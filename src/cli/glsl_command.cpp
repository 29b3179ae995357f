// heightmarch glsl: the technique as GLSL in OSMesa (llvmpipe) on the same rays as the CPU;
// --compare measures the CPU kernels beside it, interleaved, and reports conformance and the
// speed ratio with its spread.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "glsl/user_shader_text.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/run_outputs.hpp"
#include "io/atomic_file.hpp"
#include "io/json_writer.hpp"
#include "util/input_file.hpp"

namespace heightmarch::cli {
namespace {

struct GlslOptions {
  TraceOptions trace;
  std::string shader;
  bool compare = false;
};

struct Conformance {
  double same_samples = 0;  // share of rays with identical sample counts
  double p99 = 0, max = 0;  // uv difference, texels
};

Conformance conformance(const RayBatch& rays, const HitBuffers& glsl, const HitBuffers& cpu, int width, int height) {
  std::size_t same = 0, measured = 0;
  std::vector<float> differences;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    ++measured;
    same += glsl.samples[i] == cpu.samples[i];
    differences.push_back(uv_error_texels(glsl.u[i], glsl.v[i], cpu.u[i], cpu.v[i], width, height));
  }
  std::sort(differences.begin(), differences.end());
  Conformance c;
  if (differences.empty()) return c;
  c.same_samples = double(same) / double(measured);
  c.p99 = differences[std::min(differences.size() - 1, differences.size() * 99 / 100)];
  c.max = differences.back();
  return c;
}

// CPU over GLSL rays/s, per round of the interleaved repetitions.
Spread ratio_per_round(const Measurement& cpu, const Measurement& glsl) {
  const std::vector<double> a = cpu.rays_per_second(), b = glsl.rays_per_second();
  std::vector<double> ratios;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) ratios.push_back(b[i] > 0 ? a[i] / b[i] : 0.0);
  return spread_of(ratios);
}

}  // namespace

Command add_glsl_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("glsl", "run the same technique as GLSL in OSMesa (llvmpipe); --compare sets it beside the CPU");
  auto o = std::make_shared<GlslOptions>();
  add_trace_options(*command, o->trace, false);
  command->add_option("--shader", o->shader, "GLSL file defining vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)");
  command->add_flag("--compare", o->compare, "also run the CPU kernels (best ISA), interleaved, and report conformance and speed");
  return [o] {
    Configuration glsl = trace_configuration(o->trace, RunKind::glsl);
    glsl.shader_path = o->shader;
    if (!o->shader.empty()) user_source(read_input_file(o->shader, "shader file", kMaxShaderBytes), o->shader);  // before the run
    prepare_out_directory(o->trace.out);
    std::vector<Configuration> plan = {glsl};
    if (o->compare) {
      Configuration cpu = glsl;
      cpu.kind = RunKind::trace;
      cpu.shader_path.clear();
      cpu.isa = select_isa("");
      plan.push_back(cpu);
    }
    HitBuffers glsl_hits;  // row 0's, for the conformance when row 1 (the CPU) is traced
    Conformance conf;
    MeasureOptions measure;
    measure.repetitions = o->trace.repetitions;
    measure.min_seconds = 0.05;
    measure.on_traced = [&](const TracedRow& traced) {
      if (traced.row.id == 0) {
        if (o->compare) glsl_hits = traced.hits;
        if (!o->trace.out.empty()) write_run_outputs(o->trace.out, traced);
      } else {
        conf = conformance(traced.rays, glsl_hits, traced.hits, traced.map.width, traced.map.height);
      }
    };
    const MeasuredPlan run = measure_plan(plan, measure);
    const Measurement& g = run.rows.front();
    if (!o->trace.out.empty()) write_file_atomically(o->trace.out + "/metrics.json", metrics_json(g));
    GlslRunner& runner = GlslRunner::instance(g.config.threads);
    if (!o->compare) {
      if (o->trace.json) {
        std::fputs(metrics_json(g).c_str(), stdout);
      } else {
        std::printf("GLSL on %s, %s\n", runner.renderer().c_str(), runner.version().c_str());
        std::fputs(summary_text(g).c_str(), stdout);
      }
      return 0;
    }
    const Measurement& c = run.rows.back();
    const Spread ratio = ratio_per_round(c, g);
    if (o->trace.json) {
      // One document: both rows and what compares them.
      JsonWriter json;
      json.begin_object().value("renderer", runner.renderer()).value("version", runner.version());
      json.begin_object("conformance").value("cpu_backend", c.config.backend());
      g.samples_known ? json.value("identical_sample_counts", conf.same_samples) : json.null("identical_sample_counts");
      json.value("uv_difference_p99", conf.p99).value("uv_difference_max", conf.max).end_object();
      json.begin_object("cpu_over_glsl_rays_per_second")
          .value("median", ratio.median).value("min", ratio.min).value("max", ratio.max).end_object().end_object();
      std::printf("{\"glsl\": %s, \"cpu\": %s, \"comparison\": %s}\n", metrics_json(g).c_str(), metrics_json(c).c_str(),
                  json.str().c_str());
      return 0;
    }
    std::printf("GLSL on %s, %s\n", runner.renderer().c_str(), runner.version().c_str());
    std::fputs(summary_text(g).c_str(), stdout);
    std::fputs(summary_text(c).c_str(), stdout);
    std::printf("conformance with the CPU (%s): identical sample counts %s, uv difference p99 %.3g max %.3g texels\n",
                c.config.backend().c_str(),
                g.samples_known ? (std::to_string(100.0 * conf.same_samples).substr(0, 6) + "%").c_str()
                                : "unknown (brought-in shader)",
                conf.p99, conf.max);
    std::printf("speed at %d thread%s: CPU/GLSL %.2fx (%.2f-%.2f over %zu paired rounds)\n", g.config.threads,
                g.config.threads == 1 ? "" : "s", ratio.median, ratio.min, ratio.max, g.seconds.size());
    return 0;
  };
}

}  // namespace heightmarch::cli
