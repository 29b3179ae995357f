#include "heightmarch/sampler.hpp"

#include <cmath>
#include <cstdint>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/mip_chain.hpp"

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

std::string to_string(Filter filter) { return filter == Filter::bilinear ? "bilinear" : "trilinear"; }

std::vector<std::string> filter_names() {
  std::vector<std::string> names;
  for (Filter f : kFilters) names.push_back(to_string(f));
  return names;
}

Filter parse_filter(const std::string& name) {
  for (Filter f : kFilters)
    if (name == to_string(f)) return f;
  throw InputError("unknown filter '" + name + "' (bilinear or trilinear)");
}

float sample_depth(const std::vector<DepthMap>& chain, Wrap wrap, float u, float v, float lod) {
  const int first = int(std::floor(lod));
  const int second = std::min(first + 1, int(chain.size()) - 1);
  const float a = sample_depth(chain[std::size_t(first)], wrap, u, v);
  const float b = sample_depth(chain[std::size_t(second)], wrap, u, v);
  return a + (lod - float(first)) * (b - a);
}

SamplerTexture::SamplerTexture(const DepthMap& map, Wrap wrap_mode, Filter filter)
    : width(map.width), height(map.height), stride(map.width + 1), wrap(wrap_mode) {
  const auto padded = [](const DepthMap& m) { return std::size_t(m.width + 1) * std::size_t(m.height + 1); };
  std::vector<DepthMap> chain;
  std::size_t count = padded(map);
  if (filter == Filter::trilinear) {
    chain = build_mip_chain(map);
    for (std::size_t level = 1; level < chain.size(); ++level) count += padded(chain[level]);
  }
  check_memory_budget(4.0 * double(count), "the sampler's padded copy of a " + std::to_string(width) + "x" +
                                               std::to_string(height) + " depth map" +
                                               (chain.empty() ? "" : " and its mip chain"));
  texels.resize(count);
  // Column `width` and row `height` of each level hold the texel the wrap mode reads after the last one.
  std::size_t offset = 0;
  const auto lay_out = [&](const DepthMap& m) {
    const int after_x = wrap == Wrap::repeat ? 0 : m.width - 1;
    const int after_y = wrap == Wrap::repeat ? 0 : m.height - 1;
    for (int j = 0; j <= m.height; ++j) {
      const int sj = j < m.height ? j : after_y;
      float* row = &texels[offset + std::size_t(j) * std::size_t(m.width + 1)];
      for (int i = 0; i < m.width; ++i) row[i] = m.at(i, sj);
      row[m.width] = m.at(after_x, sj);
    }
    levels.push_back({std::int32_t(offset), m.width, m.height});
    offset += padded(m);
  };
  lay_out(map);
  for (std::size_t level = 1; level < chain.size(); ++level) lay_out(chain[level]);
}

}  // namespace heightmarch
