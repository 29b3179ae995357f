// heightmarch glsl: the technique (or a brought-in shader) as GLSL (OSMesa or EGL: --gl,
// --gl-device) on the same rays as the CPU; --compare measures CPU kernels beside it,
// interleaved, and reports conformance and the speed ratio with its spread; --list-devices lists
// EGL's devices.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "experiment/measurement_session.hpp"
#include "experiment/run_outputs.hpp"
#include "glsl/screen_layout.hpp"
#include "glsl/user_shader_text.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "io/atomic_file.hpp"
#include "io/json_writer.hpp"
#include "util/input_file.hpp"

namespace heightmarch::cli {
namespace {

struct GlslOptions {
  TraceOptions trace;
  GlOptions gl;
  std::string shader;
  std::string compare_with;  // --compare's technique; empty: the same, or every one for a shader
  bool list_devices = false;
};

// EGL's devices, one a line: index, name, renderer and GL version (or why no context was made),
// extensions.
int print_devices() {
  const std::vector<GlDevice> devices = list_gl_devices();
  if (devices.empty())
    std::printf("no EGL devices (this heightmarch was built without EGL, or EGL lists none)\n");
  for (const GlDevice& d : devices)
    std::printf("%d\t%s\t%s\t%s\n", d.index, printable(d.name).c_str(),
                printable(d.error.empty() ? d.renderer + ", " + d.version : "no context: " + d.error).c_str(),
                printable(d.extensions).c_str());
  return 0;
}

// Within this uv difference a brought-in shader agrees with a technique: the suite's default
// target for a p99 error (docs/recommendation.md).
constexpr double kAgreementTexels = 0.5;

struct Conformance {
  double same_samples = 0;  // share of rays with identical sample counts
  double p99 = 0, max = 0;  // uv difference, texels
  double agreeing = 0;      // share of rays within kAgreementTexels
};

Conformance conformance(const RayBatch& rays, const HitBuffers& glsl, const HitBuffers& cpu, int width,
                        int height) {
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
  c.agreeing = double(std::upper_bound(differences.begin(), differences.end(), float(kAgreementTexels)) -
                      differences.begin()) /
               double(differences.size());
  return c;
}

// CPU over GLSL rays/s, per round of the interleaved repetitions.
Spread ratio_per_round(const Measurement& cpu, const Measurement& glsl) {
  const std::vector<double> a = cpu.rays_per_second(), b = glsl.rays_per_second();
  std::vector<double> ratios;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    ratios.push_back(b[i] > 0 ? a[i] / b[i] : 0.0);
  return spread_of(ratios);
}

// The CPU techniques --compare sets beside the GLSL run: the one named, else the GLSL run's own
// technique, else (a brought-in shader) every technique, to find the one it is closest to.
std::vector<Technique> compared_techniques(const Configuration& glsl, const std::string& named) {
  if (!named.empty()) return {parse_technique(named, "")};
  if (glsl.has_technique()) return {glsl.params.technique};
  std::vector<Technique> all;
  for (const TechniqueInfo& t : techniques()) all.push_back(t.id);
  return all;
}

// One CPU row beside the GLSL row; conformance is known once the CPU row was traced.
struct Comparison {
  std::optional<Conformance> conformance;  // none: the CPU row failed its reference check
  Spread ratio;
};

void write_comparison_json(JsonWriter& json, const Measurement& glsl, const Measurement& cpu,
                           const Comparison& c) {
  json.begin_object().raw("cpu", metrics_json(cpu));
  if (c.conformance) {
    json.begin_object("conformance").value("cpu_backend", cpu.config.backend());
    glsl.samples_known ? json.value("identical_sample_counts", c.conformance->same_samples)
                       : json.null("identical_sample_counts");
    json.value("uv_difference_p99", c.conformance->p99)
        .value("uv_difference_max", c.conformance->max)
        .value("agreeing", c.conformance->agreeing)
        .value("agreeing_within_texels", kAgreementTexels)
        .end_object();
  } else {
    json.null("conformance");
  }
  if (cpu.seconds.empty() || glsl.seconds.empty())
    json.null("cpu_over_glsl_rays_per_second");
  else
    json.begin_object("cpu_over_glsl_rays_per_second")
        .value("median", c.ratio.median)
        .value("min", c.ratio.min)
        .value("max", c.ratio.max)
        .end_object();
  json.end_object();
}

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f%%", 100.0 * share);
  return buf;
}

void print_comparison(const Measurement& glsl, const Measurement& cpu, const Comparison& c) {
  std::fputs(summary_text(cpu).c_str(), stdout);
  if (!c.conformance) return;  // the summary says why
  std::printf(
      "conformance of %s with %s (%s): identical sample counts %s, uv difference p99 %.3g max %.3g texels, "
      "%s of rays within %g texel\n",
      printable(glsl.config.label()).c_str(), cpu.config.label().c_str(), cpu.config.backend().c_str(),
      glsl.samples_known ? percent(c.conformance->same_samples).c_str() : "unknown", c.conformance->p99,
      c.conformance->max, percent(c.conformance->agreeing).c_str(), kAgreementTexels);
  std::printf("speed at %d thread%s: CPU/GLSL %.2fx (%.2f-%.2f over %zu paired rounds)\n",
              glsl.config.threads, glsl.config.threads == 1 ? "" : "s", c.ratio.median, c.ratio.min,
              c.ratio.max, glsl.seconds.size());
}

}  // namespace

Command add_glsl_command(CLI::App& app) {
  CLI::App* command =
      app.add_subcommand("glsl",
                         "run a technique, or a brought-in shader, as GLSL in OSMesa or EGL "
                         "(llvmpipe, or a GPU through EGL); --compare sets it beside the CPU");
  auto o = std::make_shared<GlslOptions>();
  add_trace_options(*command, o->trace, false);
  add_gl_options(*command, o->gl);
  command->add_flag(
      "--list-devices", o->list_devices,
      "list EGL's devices (index, name, renderer, extensions) for --gl-device, and run nothing");
  command
      ->add_option(
          "--shader", o->shader,
          "GLSL file defining vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir), run instead of --technique")
      ->excludes(command->get_option("--technique"));
  CLI::Option* compare =
      command
          ->add_option(
              "--compare", o->compare_with,
              "also run the CPU kernels (best ISA) of TECHNIQUE (default: the same technique; with --shader: "
              "every technique, naming the closest), interleaved, and report conformance and speed")
          ->expected(0, 1)
          ->type_name("[TECHNIQUE]");
  return [o, compare] {
    if (o->list_devices) return print_devices();
    LayerSpec layers_asked;
    Configuration glsl = trace_configuration(o->trace, RunKind::glsl, &layers_asked);
    glsl.gl = gl_target(o->gl);
    if (!o->shader.empty()) glsl.shader = BroughtInShader{o->shader};
    if (!o->shader.empty())
      user_source(read_input_file(o->shader, "shader file", kMaxShaderBytes), o->shader);  // before the run
    if (!o->shader.empty() && glsl.view.kind == ViewSpec::Kind::rays_file &&
        glsl.params.filter == Filter::trilinear)
      std::fprintf(
          stderr,
          "heightmarch: note: a rays file has no pixel grid: its rays are drawn in rows of %d in the "
          "file's order, so texture() in %s takes its level of detail from unrelated rays (undefined "
          "there); textureLod, or textureGrad with gradients of its own, is defined "
          "(docs/techniques.md#the-gl-paths)\n",
          kRowWidth, printable(o->shader).c_str());
    std::vector<Configuration> plan = {glsl};
    if (compare->count() > 0)
      for (Technique technique : compared_techniques(glsl, o->compare_with)) {
        Configuration cpu = glsl;
        cpu.kind = RunKind::trace;
        cpu.shader.reset();
        cpu.isa = select_isa("");
        cpu.params.technique = technique;
        cpu.params.layers = layers_for(technique, layers_asked);
        cpu.params.refine = o->trace.refine;
        plan.push_back(cpu);
      }
    MeasurementSession session;
    session.check_inputs(plan);       // its map, rays, GL target and shader checked before --out is made
    std::optional<RunDirectory> dir;  // checked and locked before the run
    if (!o->trace.out.out.empty()) dir.emplace(o->trace.out.out, o->trace.out.existing());
    HitBuffers glsl_hits;  // row 0's (traced first), for the conformance of the CPU rows after it
    std::vector<Comparison> comparisons(plan.size() - 1);
    MeasureOptions measure;
    measure.repetitions = o->trace.repetitions;
    measure.min_seconds = 0.05;
    measure.on_traced = [&](const TracedRow& traced) {
      if (traced.row.id == 0) {
        if (plan.size() > 1) glsl_hits = traced.hits;
        if (dir) write_run_outputs(dir->path(), traced);
      } else {
        comparisons[traced.row.id - 1].conformance =
            conformance(traced.rays, glsl_hits, traced.hits, traced.map.width, traced.map.height);
      }
    };
    const MeasuredPlan run = measure_plan(plan, measure, session);
    const Measurement& g = run.rows.front();
    if (dir) {
      write_file_atomically(dir->path() + "/metrics.json", metrics_json(g));
      dir->complete();
    }
    // The closest CPU technique: the lowest uv difference p99 (the first of equals).
    std::optional<std::size_t> closest;
    for (std::size_t k = 0; k < comparisons.size(); ++k) {
      Comparison& c = comparisons[k];
      c.ratio = ratio_per_round(run.rows[k + 1], g);
      if (c.conformance && (!closest || c.conformance->p99 < comparisons[*closest].conformance->p99))
        closest = k;
    }
    const GlRenderer& renderer = *g.gl;
    if (o->trace.json) {
      if (comparisons.empty()) {
        std::fputs(metrics_json(g).c_str(), stdout);
        return 0;
      }
      // One document: the GLSL row, each CPU row with what compares it, and the closest.
      JsonWriter json;
      json.begin_object()
          .value("renderer", renderer.renderer)
          .value("version", renderer.version)
          .raw("glsl", metrics_json(g));
      json.begin_array("comparisons");
      for (std::size_t k = 0; k < comparisons.size(); ++k)
        write_comparison_json(json, g, run.rows[k + 1], comparisons[k]);
      json.end_array();
      closest ? json.value("closest", run.rows[*closest + 1].config.label()) : json.null("closest");
      json.end_object();
      std::fputs((json.str() + "\n").c_str(), stdout);
      return 0;
    }
    std::printf("GLSL through %s on %s (%s), %s, %s\n", display_name(renderer.path).c_str(),
                printable(renderer.renderer).c_str(), printable(renderer.device).c_str(),
                printable(renderer.version).c_str(), printable(renderer.driver).c_str());
    std::fputs(summary_text(g).c_str(), stdout);
    for (std::size_t k = 0; k < comparisons.size(); ++k) print_comparison(g, run.rows[k + 1], comparisons[k]);
    if (comparisons.size() > 1 && closest)
      std::printf("closest technique to %s: %s (uv difference p99 %.3g texels)\n",
                  printable(g.config.label()).c_str(), run.rows[*closest + 1].config.label().c_str(),
                  comparisons[*closest].conformance->p99);
    return 0;
  };
}

}  // namespace heightmarch::cli
