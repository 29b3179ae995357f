#pragma once
// GL_LINEAR level-0 sampling of a depth map (docs/conventions.md), and the layouts a texture takes
// for the packet kernels and for the GLSL.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/heightfield.hpp"

namespace heightmarch {

// The sampling formula of docs/conventions.md, written plainly with integer wrapping: x = u W - 0.5, i0 = floor(x),
// fx = x - i0, taps wrapped or clamped, blended as a + f (b - a) in x, then in y.
// The kernels' packet sampler (src/kernels/sampler.hpp) must agree with it bit for bit.
float sample_depth(const DepthMap& map, Wrap wrap, float u, float v);

// The depth map laid out for the packet sampler: one extra column and row holding the texel
// that the wrap mode puts after the last one, so the right and lower taps are always at
// index + 1 and index + stride.
struct SamplerTexture {
  int width = 0;
  int height = 0;
  int stride = 0;  // width + 1
  Wrap wrap = Wrap::repeat;
  std::vector<float> texels;  // (width + 1) x (height + 1)

  SamplerTexture() = default;
  SamplerTexture(const DepthMap& map, Wrap wrap);
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
  bool linear = false;     // GL_LINEAR, else GL_NEAREST (read with texelFetch)
  bool run_wrap = false;   // the run's wrap mode, else CLAMP_TO_EDGE
  std::vector<float> texels;
  std::vector<std::pair<std::string, std::vector<std::int32_t>>> uniforms;
};

}  // namespace heightmarch
