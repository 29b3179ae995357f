#include "heightmarch/technique.hpp"

#include <charconv>
#include <cmath>

#include "heightmarch/error.hpp"

namespace heightmarch {

const std::array<TechniqueInfo, kTechniqueCount>& techniques() {
#define HEIGHTMARCH_TECHNIQUE_INFO(id, name, layered, refine, needs, writes, search, shape, kernel, \
                                   glsl_call, color, marker, description)                           \
  TechniqueInfo{Technique::id, name,  layered,   refine, needs,  writes,                            \
                search,        shape, glsl_call, color,  marker, description},
  static const std::array<TechniqueInfo, kTechniqueCount> rows = {
      HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_INFO)};
#undef HEIGHTMARCH_TECHNIQUE_INFO
  return rows;
}

const TechniqueInfo& info(Technique technique) { return techniques()[std::size_t(technique)]; }

bool writes_visibility(const TechniqueInfo& t) {
  for (const HitChannelInfo& c : hit_channels())
    if (c.against == MeasuredAgainst::visibility && writes(t, c.id)) return true;
  return false;
}

namespace {

// A row's `writes` names optional outputs only: the others are every technique's, or no technique's.
constexpr bool writes_optional_only(Writes writes) {
  for (const HitChannelInfo& c : hit_channels())
    if (c.writer != ChannelWriter::optional && (unsigned(writes) >> unsigned(c.id)) & 1u) return false;
  return true;
}
#define HEIGHTMARCH_CHECK_WRITES(id, name, layered, refine, needs, writes, ...) \
  static_assert(writes_optional_only(writes),                                   \
                "technique " name ": writes names an output that is not optional");
HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_CHECK_WRITES)
#undef HEIGHTMARCH_CHECK_WRITES

}  // namespace

std::string to_string(Technique technique) { return std::string(info(technique).name); }

std::string technique_names() {
  std::string names;
  for (const TechniqueInfo& t : techniques()) names += (names.empty() ? "" : ", ") + std::string(t.name);
  return names;
}

Technique parse_technique(const std::string& name, const std::string& extra) {
  for (const TechniqueInfo& t : techniques())
    if (t.name == name) return t.id;
  throw InputError("unknown technique '" + name + "' (" + technique_names() +
                   (extra.empty() ? "" : ", " + extra) + ")");
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
  if (dash == std::string::npos || dash == 0) return LayerSpec::fixed(parse_layer_count(text, text));
  const int a = parse_layer_count(text.substr(0, dash), text);
  const int b = parse_layer_count(text.substr(dash + 1), text);
  if (a > b)
    throw InputError("layer spec '" + text + "': minimum " + std::to_string(a) + " exceeds maximum " +
                     std::to_string(b));
  return LayerSpec::range(a, b);
}

std::string to_string(const LayerSpec& layers) {
  if (!layers.dynamic()) return std::to_string(int(layers.min_layers));
  return std::to_string(int(layers.min_layers)) + "-" + std::to_string(int(layers.max_layers));
}

LayerSpec layers_for(Technique technique, const LayerSpec& spec) {
  return info(technique).layered ? spec : LayerSpec::fixed(1);
}

void check(const TechniqueParams& params) {
  const int technique = int(params.technique);
  if (technique < 0 || technique >= kTechniqueCount)
    throw InputError("technique " + std::to_string(technique) + " is not one of the " +
                     std::to_string(kTechniqueCount) + " of the registry");
  const LayerSpec& l = params.layers;
  if (!(l.min_layers >= 1.0f && l.min_layers <= l.max_layers && l.max_layers <= float(kMaxLayers)))
    throw InputError("layers " + std::to_string(l.min_layers) + "-" + std::to_string(l.max_layers) +
                     ": not a count or range within [1, " + std::to_string(kMaxLayers) + "]");
  if (!(params.scale >= 0.0f && params.scale <= 1.0f))
    throw InputError("scale " + std::to_string(params.scale) + " is outside [0, 1]");
  if (params.refine_steps() < 0 || params.refine_steps() > kMaxRefineSteps)
    throw InputError("refine steps " + std::to_string(params.refine_steps()) + " outside [0, " +
                     std::to_string(kMaxRefineSteps) + "]");
  if (params.wrap != Wrap::repeat && params.wrap != Wrap::clamp)
    throw InputError("wrap mode " + std::to_string(int(params.wrap)) + " is neither repeat nor clamp");
  if (params.filter != Filter::bilinear && params.filter != Filter::trilinear)
    throw InputError("filter " + std::to_string(int(params.filter)) + " is neither bilinear nor trilinear");
  const float* l3 = params.light;
  const float length = std::sqrt(l3[0] * l3[0] + l3[1] * l3[1] + l3[2] * l3[2]);
  if (!std::isfinite(length) || !(l3[2] > 0.0f))
    throw InputError("light direction must be finite and above the plane (z > 0)");
  if (!(l3[2] / length >= 1e-3f))  // a light along the plane would need unbounded shadow marches
    throw InputError("light direction grazes the plane: z / |L| = " + std::to_string(l3[2] / length) +
                     ", must be at least 0.001 (0.06 degrees above it)");
}

void validate(TechniqueParams& params) {
  check(params);
  const float* l = params.light;
  const float length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  for (int i = 0; i < 3; ++i) params.light[i] = l[i] / length;
}

}  // namespace heightmarch
