#pragma once
// The precomputed textures a technique reads besides the depth map: one row per kind, and the
// only list of them. A technique's registry row names the kinds it reads (`needs`,
// technique_list.hpp); one builder makes them for the CPU Tracer and the GLSL worker alike, once
// per depth map and wrap mode.
//
// X(id, type, builder, GL texture unit, GLSL sampler)
// - id: the kind's flag Needs::id, its member of PrecomputedTextures and its slot of the kernels'
//   KernelTexture (src/kernels/kernel_abi.hpp), which type::slot() fills.
// - builder: std::shared_ptr<const type> builder(const DepthMap&, Wrap), which sets the texture's
//   build_seconds (a cached one: those of its first build).
// - GL texture unit and GLSL sampler: where the GLSL worker binds type::gl_image() (its int
//   uniforms beside it); units 0 to 3 are the depth map's and the rays' (T, V and their gradients).
//
// Adding a kind: its row here, its type (with slot(), gl_image() and build_seconds) and builder,
// and the sampler uniform in the GLSL of the techniques that read it.
#include <memory>

#include "heightmarch/cone_map.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/min_depth_pyramid.hpp"

#define HEIGHTMARCH_PRECOMPUTED_TEXTURES(X)                                            \
  X(min_depth_pyramid, MinDepthPyramid, build_min_depth_pyramid, 4, "minDepthPyramid") \
  X(cone_map, ConeMap, cached_cone_map, 5, "coneMap")

namespace heightmarch {

#define HEIGHTMARCH_PRECOMPUTED_ENUM(id, ...) id,
enum class PrecomputedKind { HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_PRECOMPUTED_ENUM) };
#undef HEIGHTMARCH_PRECOMPUTED_ENUM
#define HEIGHTMARCH_PRECOMPUTED_COUNT(...) +1
inline constexpr int kPrecomputedKindCount =
    0 HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_PRECOMPUTED_COUNT);
#undef HEIGHTMARCH_PRECOMPUTED_COUNT

// What a technique reads besides the depth map (flags, combinable).
#define HEIGHTMARCH_PRECOMPUTED_FLAG(id, ...) id = 1u << unsigned(PrecomputedKind::id),
enum class Needs : unsigned { nothing = 0, HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_PRECOMPUTED_FLAG) };
#undef HEIGHTMARCH_PRECOMPUTED_FLAG
constexpr Needs operator|(Needs a, Needs b) { return Needs(unsigned(a) | unsigned(b)); }
constexpr bool has(Needs set, Needs one) { return (unsigned(set) & unsigned(one)) != 0; }

struct PrecomputedTextures {
#define HEIGHTMARCH_PRECOMPUTED_MEMBER(id, type, ...) std::shared_ptr<const type> id;
  HEIGHTMARCH_PRECOMPUTED_TEXTURES(HEIGHTMARCH_PRECOMPUTED_MEMBER)
#undef HEIGHTMARCH_PRECOMPUTED_MEMBER
  // Wall time the textures took to build (a cached one: its first build), apart from any
  // trace's time: the preprocessing a renderer pays once per depth map.
  double build_seconds = 0;
};

// The min-depth pyramid's builder (the cone map's is cached_cone_map, cone_map.hpp).
std::shared_ptr<const MinDepthPyramid> build_min_depth_pyramid(const DepthMap& map, Wrap wrap);

// Builds what `needs` lists for this depth map and wrap mode; nothing for Needs::nothing.
PrecomputedTextures build_precomputed(const DepthMap& map, Wrap wrap, Needs needs);

}  // namespace heightmarch
