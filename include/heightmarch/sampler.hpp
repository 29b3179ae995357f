#pragma once
// Sampling a depth map (docs/conventions.md): GL_LINEAR on level 0, or trilinear over its mip
// chain; and the layouts a texture takes for the packet kernels and for the GLSL.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/heightfield.hpp"

namespace heightmarch {

// How a technique's samples read the depth map: bilinear (GL_LINEAR on level 0, the surface the
// exact reference intersects) or trilinear (GL_LINEAR_MIPMAP_LINEAR over the mip chain, at the
// level of detail of the ray's pixel footprint: heightmarch/mip_chain.hpp).
enum class Filter { bilinear, trilinear };
inline constexpr Filter kFilters[] = {Filter::bilinear, Filter::trilinear};
inline constexpr int kFilterCount = 2;
std::string to_string(Filter filter);          // "bilinear", "trilinear"
Filter parse_filter(const std::string& name);  // throws InputError naming both
std::vector<std::string> filter_names();

// The sampling formula of docs/conventions.md, written plainly with integer wrapping: x = u W - 0.5, i0 =
// floor(x), fx = x - i0, taps wrapped or clamped, blended as a + f (b - a) in x, then in y. The kernels'
// packet sampler (src/kernels/packet_sampler.hpp) must agree with it bit for bit.
float sample_depth(const DepthMap& map, Wrap wrap, float u, float v);

// Trilinear: the formula above on the two levels of the mip chain (build_mip_chain) around the
// level of detail lod (level_of_detail(), in [0, last level]), blended as a + f (b - a) with f the
// fraction of lod; at a whole lod, that level alone.
float sample_depth(const std::vector<DepthMap>& chain, Wrap wrap, float u, float v, float lod);

// One level of a SamplerTexture: where it starts in the texels, and its sides.
struct SamplerLevel {
  std::int32_t offset = 0;
  int width = 0, height = 0;  // its stride is width + 1
};

// The depth map laid out for the packet sampler: one extra column and row holding the texel
// that the wrap mode puts after the last one, so the right and lower taps are always at
// index + 1 and index + stride. Trilinear: the levels of its mip chain follow, each laid out alike.
struct SamplerTexture {
  int width = 0;
  int height = 0;
  int stride = 0;  // width + 1
  Wrap wrap = Wrap::repeat;
  std::vector<float> texels;         // level 0: (width + 1) x (height + 1); then the chain's levels
  std::vector<SamplerLevel> levels;  // level 0 alone, or every level of the chain

  SamplerTexture() = default;
  SamplerTexture(const DepthMap& map, Wrap wrap, Filter filter = Filter::bilinear);
};

// A precomputed texture as the packet kernels read it (its kind's slot in KernelTexture): its
// texels, and for a pyramid where each level starts and how many levels it has.
struct TextureSlot {
  const float* texels = nullptr;
  const std::int32_t* level_offsets = nullptr;
  int levels = 0;
};

// A precomputed texture as the GLSL reads it: a float texture of 1 or 2 channels, row-major, and
// the int uniforms (single values or arrays) that say how to read it.
struct GlImage {
  int width = 0, height = 0, channels = 1;
  bool linear = false;    // GL_LINEAR, else GL_NEAREST (read with texelFetch)
  bool run_wrap = false;  // the run's wrap mode, else CLAMP_TO_EDGE
  std::vector<float> texels;
  std::vector<std::pair<std::string, std::vector<std::int32_t>>> uniforms;
};

}  // namespace heightmarch
