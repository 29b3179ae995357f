#include "heightmarch/sampler.hpp"

#include <cmath>
#include <cstdint>
#include <string>

#include "heightmarch/memory_budget.hpp"

namespace heightmarch {
namespace {

// Texel index of tap i along an axis of n texels.
long long wrap_index(long long i, long long n, Wrap wrap) {
  if (wrap == Wrap::clamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  const long long r = i % n;
  return r < 0 ? r + n : r;
}

}  // namespace

float sample_depth(const DepthMap& map, Wrap wrap, float u, float v) {
  const float x = u * float(map.width) - 0.5f;
  const float y = v * float(map.height) - 0.5f;
  const float x0 = std::floor(x);
  const float y0 = std::floor(y);
  const float fx = x - x0;
  const float fy = y - y0;
  const long long i0 = wrap_index((long long)x0, map.width, wrap);
  const long long i1 = wrap_index((long long)x0 + 1, map.width, wrap);
  const long long j0 = wrap_index((long long)y0, map.height, wrap);
  const long long j1 = wrap_index((long long)y0 + 1, map.height, wrap);
  const float t00 = map.at(int(i0), int(j0)), t10 = map.at(int(i1), int(j0));
  const float t01 = map.at(int(i0), int(j1)), t11 = map.at(int(i1), int(j1));
  const float top = t00 + fx * (t10 - t00);
  const float bottom = t01 + fx * (t11 - t01);
  return top + fy * (bottom - top);
}

SamplerTexture::SamplerTexture(const DepthMap& map, Wrap wrap_mode)
    : width(map.width), height(map.height), stride(map.width + 1), wrap(wrap_mode) {
  const std::size_t count = std::size_t(stride) * std::size_t(height + 1);
  check_memory_budget(4.0 * double(count), "the sampler's padded copy of a " + std::to_string(width) + "x" +
                                               std::to_string(height) + " depth map");
  texels.resize(count);
  // Column `width` and row `height` hold the texel the wrap mode reads after the last one.
  const int after_x = wrap == Wrap::repeat ? 0 : width - 1;
  const int after_y = wrap == Wrap::repeat ? 0 : height - 1;
  for (int j = 0; j <= height; ++j) {
    const int sj = j < height ? j : after_y;
    float* row = &texels[std::size_t(j) * std::size_t(stride)];
    for (int i = 0; i < width; ++i) row[i] = map.at(i, sj);
    row[width] = map.at(after_x, sj);
  }
}

}  // namespace heightmarch
