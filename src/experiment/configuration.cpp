#include "heightmarch/configuration.hpp"

#include <cstring>
#include <filesystem>

namespace heightmarch {

std::string to_string(RunKind kind) {
  switch (kind) {
    case RunKind::trace: return "trace";
    case RunKind::glsl: return "glsl";
    case RunKind::roofline: return "roofline";
    case RunKind::ceiling: return "ceiling";
    case RunKind::naive: return "naive";
    case RunKind::autovec: return "autovec";
    case RunKind::exact: return "exact";
  }
  return "?";
}

std::string purpose_name(unsigned bit) {
  static const char* const names[kPurposeCount] = {"matrix", "isa",     "glsl",   "roofline", "naive",
                                                   "sweep",  "gallery", "claims", "command", "large-maps",
                                                   "exact"};
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
  switch (kind) {
    case RunKind::trace:
    case RunKind::roofline:
    case RunKind::ceiling:
    case RunKind::autovec: return to_string(isa);
    case RunKind::glsl: return "glsl";
    case RunKind::naive: return "naive";
    case RunKind::exact: return "exact";
  }
  return "?";
}

bool Configuration::same_measurement(const Configuration& o) const {
  const TechniqueParams &a = params, &b = o.params;
  const bool same_params = (!has_technique() || a.technique == b.technique) && a.layers == b.layers &&
                           a.refine_steps() == b.refine_steps() && a.scale == b.scale && a.wrap == b.wrap &&
                           a.discard == b.discard && std::memcmp(a.light, b.light, sizeof a.light) == 0;
  const bool same_isa = !on_isa() || isa == o.isa;
  return kind == o.kind && heightfield == o.heightfield && view == o.view && same_params && same_isa &&
         threads == o.threads && shader == o.shader;
}

std::string benchmark_name(const Configuration& c, int map_width, int map_height) {
  static const char* const prefixes[] = {"BM_Trace",     "BM_GLSL",        "BM_SamplerRoofline", "BM_ComputeCeiling",
                                         "BM_NaivePort", "BM_AutoVecPort", "BM_Exact"};
  std::string name = std::string(prefixes[int(c.kind)]) + "/heightfield:" + c.heightfield.label();
  if (c.shader) name.append("/").append(c.shader->label());
  if (c.has_technique()) name += "/technique:" + to_string(c.params.technique);
  if (c.kind != RunKind::exact) name += "/layers:" + to_string(c.params.layers);
  name += "/isa:" + (c.kind == RunKind::naive ? std::string("scalar-naive") : c.backend()) +
          "/threads:" + std::to_string(c.threads);
  name += c.view.kind == ViewSpec::Kind::perspective
              ? "/view:" + std::to_string(c.view.width) + "x" + std::to_string(c.view.height)
              : "/view:" + describe(c.view);
  return name + "/depth_map:" + std::to_string(map_width) + "x" + std::to_string(map_height);
}

}  // namespace heightmarch
