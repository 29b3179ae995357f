#pragma once
// The techniques of docs/techniques.md (one registry, technique_list.hpp) and their parameters.
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "heightmarch/hits.hpp"
#include "heightmarch/precomputed.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique_list.hpp"

namespace heightmarch {

// What a technique writes besides its hit (uv, depth, samples): the list's `optional` outputs
// (heightmarch/hits.hpp) it sets, such as a shadow factor towards the light (flags, combinable;
// only the optional rows' flags mean anything in a registry row, technique.cpp checks).
#define HEIGHTMARCH_WRITES_FLAG(name, ...) name = 1u << unsigned(HitChannel::name),
enum class Writes : unsigned { hit = 0, HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_WRITES_FLAG) };
#undef HEIGHTMARCH_WRITES_FLAG
constexpr Writes operator|(Writes a, Writes b) { return Writes(unsigned(a) | unsigned(b)); }

// How an ISA packs a technique's rays: a layered march runs well as two native packets in flight
// where the ISA says so (isa_list); a divergent walk with a large state per lane runs as one.
enum class KernelShape { march, walk };

#define HEIGHTMARCH_TECHNIQUE_ENUM(id, ...) id,
enum class Technique { HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_ENUM) };
#undef HEIGHTMARCH_TECHNIQUE_ENUM

#define HEIGHTMARCH_TECHNIQUE_COUNT(...) +1
inline constexpr int kTechniqueCount = 0 HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_COUNT);
#undef HEIGHTMARCH_TECHNIQUE_COUNT

// One row of the registry.
struct TechniqueInfo {
  Technique id;
  std::string_view name;  // on the command line and in results
  bool layered;           // takes a layer spec; otherwise one sample ("1")
  int refine;             // its default --refine (ignored by techniques that do not refine)
  Needs needs;            // precomputed textures it reads
  Writes writes;
  bool search;  // one of the searches timed at every ISA and thread count
  KernelShape shape;
  std::string_view glsl_call;  // the GLSL expression the harness evaluates
  std::string_view color, marker;
  std::string_view description;  // one line, for --help and the report
};

const std::array<TechniqueInfo, kTechniqueCount>& techniques();
// Whether the technique writes the output: its hit always, an optional one where its row says so.
constexpr bool writes(const TechniqueInfo& t, HitChannel channel) {
  return info(channel).writer == ChannelWriter::hit ||
         (info(channel).writer == ChannelWriter::optional && (unsigned(t.writes) >> unsigned(channel)) & 1u);
}
// The filter a technique's samples read under `filter`: a walk reads texels of level 0 whatever the
// filter (maxmip solves the level-0 surface), a march the filter asked for. Each ISA's kernel
// table (src/isa/kernel_table.hpp) and the exact hit on the surface a ray reads (exact.hpp) take it
// from here.
constexpr Filter filter_read(KernelShape shape, Filter filter) {
  return shape == KernelShape::walk ? Filter::bilinear : filter;
}
// Whether it writes an output measured against the light's visibility (its own measure, beside the
// hit's): the exact reference then walks towards the light too.
bool writes_visibility(const TechniqueInfo& t);
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
  static constexpr LayerSpec fixed(int n) { return {float(n), float(n)}; }
  static constexpr LayerSpec range(int a, int b) { return {float(a), float(b)}; }
  bool dynamic() const { return min_layers != max_layers; }
  friend bool operator==(const LayerSpec&, const LayerSpec&) = default;
};
inline constexpr int kMaxLayers = 4096;
LayerSpec parse_layer_spec(const std::string& text);  // throws InputError
std::string to_string(const LayerSpec& layers);
// What a technique runs with: the spec for a layered one, "1" (one sample) otherwise.
LayerSpec layers_for(Technique technique, const LayerSpec& spec);

// The tutorial's layer count for a ray of view cosine cos_theta (V.z): N, or for a dynamic spec
// mix(max, min, |cos_theta|) = max (1 - |cos|) + min |cos|. Not rounded. The one formula for the
// packet kernels (F = vfloat<W>) and scalar code (F = float); the GLSL prelude has its twin.
template <class F>
F layer_count(float min_layers, float max_layers, F cos_theta) {
  using std::abs;
  if (min_layers == max_layers) return F(max_layers);
  const F a = abs(cos_theta);
  return F(max_layers) * (F(1.0f) - a) + F(min_layers) * a;
}

inline constexpr int kMaxRefineSteps = 64;

struct TechniqueParams {
  Technique technique = Technique::pom;
  LayerSpec layers;
  // relief's halvings, secant's regula falsi steps, cone's halvings; none: the technique's
  // registry default (refine_steps() resolves it)
  std::optional<int> refine;
  float scale = 0.1f;  // height scale s
  Wrap wrap = Wrap::repeat;
  Filter filter = Filter::bilinear;  // how samples read the depth map (sampler.hpp)
  bool discard = false;              // the tutorial's discard of a final uv outside [0,1]^2
  float light[3] = {0.5773503f, 0.5773503f, 0.5773503f};  // unit vector towards the light

  // Not value_or, whose argument is always evaluated: a broken technique (a message) would index
  // the registry.
  int refine_steps() const { return refine ? *refine : info(technique).refine; }
  // What its samples read (filter_read): the surface its search error is measured against.
  Filter filter_read() const { return heightmarch::filter_read(info(technique).shape, filter); }
};

// The one check of a run's parameters, for the command line and every message the GLSL worker
// takes alike: a technique of the registry, layers within [1, kMaxLayers] (min <= max), a scale
// in [0, 1], refine steps in [0, kMaxRefineSteps], a known wrap mode and filter, a finite light above the
// plane and not grazing it (NaN fails every test). Throws InputError.
void check(const TechniqueParams& params);

// check(), then normalises the light.
void validate(TechniqueParams& params);

}  // namespace heightmarch
