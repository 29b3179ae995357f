#pragma once
// The precomputed textures a technique reads besides the depth map (its registry row's `needs`,
// technique_list.hpp), built by one builder for the CPU Tracer and the GLSL worker alike.
#include <memory>

#include "heightmarch/cone_map.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/min_depth_pyramid.hpp"

namespace heightmarch {

// What a technique reads besides the depth map: precomputed textures, built once per depth map
// and wrap mode by one builder for the CPU and GLSL alike (flags, combinable).
enum class Needs : unsigned { nothing = 0, min_depth_pyramid = 1u << 0, cone_map = 1u << 1 };
constexpr Needs operator|(Needs a, Needs b) { return Needs(unsigned(a) | unsigned(b)); }
constexpr bool has(Needs set, Needs one) { return (unsigned(set) & unsigned(one)) != 0; }

struct PrecomputedTextures {
  std::shared_ptr<const MinDepthPyramid> pyramid;  // Needs::min_depth_pyramid
  std::shared_ptr<const ConeMap> cone_map;         // Needs::cone_map (cached per map and wrap)
  // Wall time the textures took to build (a cached cone map: its first build), apart from any
  // trace's time: the preprocessing a renderer pays once per depth map.
  double build_seconds = 0;
};

// Builds what `needs` lists for this depth map and wrap mode; nothing for Needs::nothing.
PrecomputedTextures build_precomputed(const DepthMap& map, Wrap wrap, Needs needs);

}  // namespace heightmarch
