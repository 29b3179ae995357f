#include "heightmarch/technique.hpp"

#include <charconv>
#include <cmath>

#include "heightmarch/error.hpp"

namespace heightmarch {

const std::vector<Technique>& all_techniques() {
  static const std::vector<Technique> techniques = {
      Technique::parallax, Technique::parallax_limited, Technique::steep, Technique::steep_limited,
      Technique::relief,   Technique::pom,              Technique::shadow, Technique::exact};
  return techniques;
}

std::string to_string(Technique technique) {
  switch (technique) {
    case Technique::parallax: return "parallax";
    case Technique::parallax_limited: return "parallax-limited";
    case Technique::steep: return "steep";
    case Technique::steep_limited: return "steep-limited";
    case Technique::relief: return "relief";
    case Technique::pom: return "pom";
    case Technique::shadow: return "shadow";
    case Technique::exact: return "exact";
  }
  return "?";
}

Technique parse_technique(const std::string& name) {
  std::string names;
  for (Technique t : all_techniques()) {
    if (to_string(t) == name) return t;
    names += (names.empty() ? "" : ", ") + to_string(t);
  }
  throw InputError("unknown technique '" + name + "' (" + names + ")");
}

namespace {

int parse_layer_count(const std::string& text, const std::string& spec) {
  int value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end)
    throw InputError("layer spec '" + spec + "': '" + text + "' is not a whole number (N or A-B)");
  if (value < 1 || value > kMaxLayers)
    throw InputError("layer spec '" + spec + "': " + text + " layers is outside [1, " +
                     std::to_string(kMaxLayers) + "]");
  return value;
}

}  // namespace

LayerSpec parse_layer_spec(const std::string& text) {
  const auto dash = text.find('-');
  if (dash == std::string::npos || dash == 0) {
    const float n = float(parse_layer_count(text, text));
    return {n, n};
  }
  const int a = parse_layer_count(text.substr(0, dash), text);
  const int b = parse_layer_count(text.substr(dash + 1), text);
  if (a > b) throw InputError("layer spec '" + text + "': minimum " + std::to_string(a) + " exceeds maximum " + std::to_string(b));
  return {float(a), float(b)};
}

std::string to_string(const LayerSpec& layers) {
  if (!layers.dynamic()) return std::to_string(int(layers.min_layers));
  return std::to_string(int(layers.min_layers)) + "-" + std::to_string(int(layers.max_layers));
}

void validate(TechniqueParams& params) {
  if (!(params.scale >= 0.0f && params.scale <= 1.0f))
    throw InputError("scale " + std::to_string(params.scale) + " is outside [0, 1]");
  if (params.refine_steps < 0 || params.refine_steps > kMaxRefineSteps)
    throw InputError("refine steps " + std::to_string(params.refine_steps) + " outside [0, " +
                     std::to_string(kMaxRefineSteps) + "]");
  const float* l = params.light;
  const float length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  if (!std::isfinite(length) || !(l[2] > 0.0f) || !(l[2] / length >= 1e-3f))
    throw InputError("light direction must be finite and above the plane (z > 0)");
  for (int i = 0; i < 3; ++i) params.light[i] = l[i] / length;
}

}  // namespace heightmarch
