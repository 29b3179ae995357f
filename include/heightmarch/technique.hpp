#pragma once
// The techniques of SPEC section 4 and their parameters.
#include <string>
#include <vector>

#include "heightmarch/sampler.hpp"

namespace heightmarch {

enum class Technique { parallax, parallax_limited, steep, steep_limited, relief, pom, shadow, exact };

const std::vector<Technique>& all_techniques();  // exact last
std::string to_string(Technique technique);
Technique parse_technique(const std::string& name);  // throws InputError

// A fixed count N (min == max) or the tutorial's dynamic range A-B: N = mix(B, A, |V.z|).
struct LayerSpec {
  float min_layers = 32.0f;
  float max_layers = 32.0f;
  bool dynamic() const { return min_layers != max_layers; }
};
inline constexpr int kMaxLayers = 4096;
LayerSpec parse_layer_spec(const std::string& text);  // throws InputError
std::string to_string(const LayerSpec& layers);

inline constexpr int kMaxRefineSteps = 64;

struct TechniqueParams {
  Technique technique = Technique::pom;
  LayerSpec layers;
  int refine_steps = 5;          // relief's binary search halvings
  float scale = 0.1f;            // height scale s
  Wrap wrap = Wrap::repeat;
  bool discard = false;          // the tutorial's discard of a final uv outside [0,1]^2
  float light[3] = {0.5773503f, 0.5773503f, 0.5773503f};  // unit vector towards the light
};

// Throws InputError for a scale outside [0, 1] (NaN included), bad refine counts, a light below
// the plane; normalises the light.
void validate(TechniqueParams& params);

}  // namespace heightmarch
