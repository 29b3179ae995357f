#pragma once
// The techniques of docs/techniques.md (one registry, technique_list.hpp) and their parameters.
#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "heightmarch/sampler.hpp"
#include "heightmarch/technique_list.hpp"

namespace heightmarch {

#define HEIGHTMARCH_TECHNIQUE_ENUM(id, ...) id,
enum class Technique { HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_ENUM) };
#undef HEIGHTMARCH_TECHNIQUE_ENUM

#define HEIGHTMARCH_TECHNIQUE_COUNT(...) +1
inline constexpr int kTechniqueCount = 0 HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_COUNT);
#undef HEIGHTMARCH_TECHNIQUE_COUNT

// One row of the registry.
struct TechniqueInfo {
  Technique id;
  std::string_view name;         // on the command line and in results
  bool layered;                  // takes a layer spec; otherwise one sample ("1")
  int refine;                    // its default --refine (ignored by techniques that do not refine)
  std::string_view glsl_call;    // the GLSL expression the harness evaluates
  std::string_view color, marker;
  std::string_view description;  // one line, for --help and the report
};

const std::array<TechniqueInfo, kTechniqueCount>& techniques();
const TechniqueInfo& info(Technique technique);
std::string to_string(Technique technique);

// Throws InputError naming the known techniques. `extra` lists names the caller accepts beside
// the registry's (e.g. "exact"), only for the message.
Technique parse_technique(const std::string& name, const std::string& extra = "");
// Every technique name, comma-separated, for help texts.
std::string technique_names();

// A fixed count N (min == max) or the tutorial's dynamic range A-B: N = mix(B, A, |V.z|).
struct LayerSpec {
  float min_layers = 32.0f;
  float max_layers = 32.0f;
  bool dynamic() const { return min_layers != max_layers; }
  friend bool operator==(const LayerSpec&, const LayerSpec&) = default;
};
inline constexpr int kMaxLayers = 4096;
LayerSpec parse_layer_spec(const std::string& text);  // throws InputError
std::string to_string(const LayerSpec& layers);
// What a technique runs with: the spec for a layered one, "1" (one sample) otherwise.
LayerSpec layers_for(Technique technique, const LayerSpec& spec);

inline constexpr int kMaxRefineSteps = 64;

struct TechniqueParams {
  Technique technique = Technique::pom;
  LayerSpec layers;
  int refine_steps = 5;          // relief's halvings, secant's regula falsi steps, cone's halvings
                                 // (configurations take the technique's default from the registry)
  float scale = 0.1f;            // height scale s
  Wrap wrap = Wrap::repeat;
  bool discard = false;          // the tutorial's discard of a final uv outside [0,1]^2
  float light[3] = {0.5773503f, 0.5773503f, 0.5773503f};  // unit vector towards the light
};

// Throws InputError for a scale outside [0, 1] (NaN included), bad refine counts, a light below
// the plane; normalises the light.
void validate(TechniqueParams& params);

}  // namespace heightmarch
