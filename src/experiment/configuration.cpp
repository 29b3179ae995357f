#include "experiment/configuration.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"

namespace heightmarch {

const RunKindInfo& info(RunKind kind) {
#define HEIGHTMARCH_RUN_KIND_INFO(id, ...) RunKindInfo{RunKind::id, __VA_ARGS__},
  static const RunKindInfo rows[] = {HEIGHTMARCH_RUN_KINDS(HEIGHTMARCH_RUN_KIND_INFO)};
#undef HEIGHTMARCH_RUN_KIND_INFO
  return rows[int(kind)];
}

std::string to_string(RunKind kind) { return std::string(info(kind).name); }

std::string purpose_name(unsigned bit) {
  static const char* const names[kPurposeCount] = {
      "matrix", "isa",     "glsl",       "roofline", "naive",    "sweep",       "gallery",
      "claims", "command", "large-maps", "exact",    "held-out", "calibration", "filters"};
  for (unsigned i = 0; i < kPurposeCount; ++i)
    if (bit == (1u << i)) return names[i];
  return "?";
}

std::string BroughtInShader::label() const {
  return "shader:" + std::filesystem::path(path).filename().string();
}

std::string Configuration::label() const {
  if (shader) return shader->label();
  return has_technique() ? to_string(params.technique) : to_string(kind);
}

std::string Configuration::backend() const {
  const std::string_view label = info(kind).backend_label;
  return label.empty() ? to_string(isa) : std::string(label);
}

bool Configuration::same_measurement(const Configuration& o) const {
  const TechniqueParams &a = params, &b = o.params;
  const bool same_params = (!has_technique() || a.technique == b.technique) && a.layers == b.layers &&
                           a.refine_steps() == b.refine_steps() && a.scale == b.scale && a.wrap == b.wrap &&
                           (!takes_filter(kind) || a.filter == b.filter) && a.discard == b.discard &&
                           std::memcmp(a.light, b.light, sizeof a.light) == 0;
  const bool same_isa = !on_isa() || isa == o.isa;
  const bool same_gl = kind != RunKind::glsl || gl == o.gl;
  return kind == o.kind && heightfield == o.heightfield && view == o.view && same_params && same_isa &&
         threads == o.threads && shader == o.shader && same_gl;
}

std::string plan_line(const Configuration& c) {
  std::string purposes;
  for (unsigned i = 0; i < kPurposeCount; ++i)
    if (c.purposes & (1u << i)) purposes += (purposes.empty() ? "" : ",") + purpose_name(1u << i);
  const std::string layers = c.has_layers() ? to_string(c.params.layers) : "";
  // a line for a terminal: names from the user's files (map, shader, rays) through printable()
  return printable(c.heightfield.label()) + "\t" + to_string(c.kind) + "\t" + printable(c.label()) + "\t" +
         layers + "\t" + c.backend() + "\t" + std::to_string(c.threads) + "\t" + printable(describe(c.view)) +
         "\t" + (c.has_filter() ? to_string(c.params.filter) : "-") + "\t" +
         (c.timed ? "timed" : "accuracy") + "\t" + purposes;
}

void add_to_plan(std::vector<Configuration>& plan, const Configuration& config) {
  for (Configuration& c : plan)
    if (c.same_measurement(config)) {
      c.purposes |= config.purposes;
      c.timed = c.timed || config.timed;
      c.supersample = std::max(c.supersample, config.supersample);
      return;
    }
  plan.push_back(config);
}

std::string benchmark_name(const Configuration& c, int map_width, int map_height) {
  const RunKindInfo& kind = info(c.kind);
  // A name's fields are split at '/': a label that is a path (a/rock.png) keeps its slashes as %2F.
  std::string label;
  for (char ch : c.heightfield.label()) label += ch == '/' ? std::string("%2F") : std::string(1, ch);
  std::string name = std::string(kind.benchmark_prefix) + "/heightfield:" + label;
  if (c.shader) name.append("/").append(c.shader->label());
  if (c.has_technique()) name += "/technique:" + to_string(c.params.technique);
  if (c.has_layers()) name += "/layers:" + to_string(c.params.layers);
  name += "/isa:" + (kind.benchmark_isa_label.empty() ? c.backend() : std::string(kind.benchmark_isa_label)) +
          "/threads:" + std::to_string(c.threads);
  if (c.kind == RunKind::glsl) {
    const GlTarget gl = c.gl.path ? c.gl : resolved(c.gl);
    name += "/gl:" + to_string(*gl.path) + (gl.device.empty() ? "" : "@" + gl.device);
  }
  name += "/view:" + benchmark_view(c.view) + "/depth_map:" + std::to_string(map_width) + "x" +
          std::to_string(map_height);
  // Bilinear by no segment, as names have always read.
  if (takes_filter(c.kind) && c.params.filter != Filter::bilinear)
    name += "/filter:" + to_string(c.params.filter);
  return name;
}

std::string benchmark_view(const ViewSpec& view) {
  // The single default view at its default angles by its size alone, as names have always read.
  if (view.kind == ViewSpec::Kind::perspective && !view.around && view.seed == 0 && view.fresh_rays == 0 &&
      view.near_degrees == kDefaultNearDegrees && view.far_degrees == kDefaultFarDegrees)
    return std::to_string(view.width) + "x" + std::to_string(view.height);
  // Others as described, in one field: "around:1024x1024", "tutorial:16:566x425".
  std::string segment;
  for (char ch : describe(view))
    segment += ch == ' ' ? std::string(":") : ch == '/' ? std::string("%2F") : std::string(1, ch);
  return segment;
}

}  // namespace heightmarch
