#pragma once
// GL_LINEAR level-0 sampling of a depth map (docs/conventions.md).
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

}  // namespace heightmarch
