#include "heightmarch/min_depth_pyramid.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "heightmarch/memory_budget.hpp"

namespace heightmarch {

void MinDepthPyramid::add_level(int bx, int by) {
  offsets_.push_back(std::int32_t(min_depth_.size()));
  blocks_x_.push_back(bx);
  blocks_y_.push_back(by);
  min_depth_.resize(min_depth_.size() + std::size_t(bx) * std::size_t(by), 1.0f);
}

void MinDepthPyramid::start(int cells_x, int cells_y, const std::string& what) {
  // Every level at once (a quarter of the one before, plus an edge): no reallocation doubles it.
  const std::size_t entries = std::size_t(cells_x) * std::size_t(cells_y) * 4 / 3 +
                              2 * (std::size_t(cells_x) + std::size_t(cells_y) + kMaxLevels);
  check_memory_budget(4.0 * double(entries), what);
  min_depth_.reserve(entries);
  add_level(cells_x, cells_y);
}

void MinDepthPyramid::reduce(bool repeat) {
  while (levels() < kMaxLevels) {
    const int fine = levels() - 1;
    const int fx = blocks_x(fine), fy = blocks_y(fine);
    if (fx == 1 && fy == 1) break;
    if (repeat && (fx % 2 != 0 || fy % 2 != 0)) break;
    add_level((fx + 1) / 2, (fy + 1) / 2);
    const int coarse = levels() - 1;
    float* out = &min_depth_[std::size_t(offsets_[std::size_t(coarse)])];
    const float* in = &min_depth_[std::size_t(offsets_[std::size_t(fine)])];
    for (int j = 0; j < fy; ++j)
      for (int i = 0; i < fx; ++i) {
        float& m = out[std::size_t(j / 2) * std::size_t(blocks_x(coarse)) + std::size_t(i / 2)];
        m = std::min(m, in[std::size_t(j) * std::size_t(fx) + std::size_t(i)]);
      }
  }
}

MinDepthPyramid::MinDepthPyramid(const DepthMap& map, Wrap wrap) {
  const bool repeat = wrap == Wrap::repeat;
  const int cells_x = repeat ? map.width : map.width - 1;
  const int cells_y = repeat ? map.height : map.height - 1;
  if (cells_x < 1 || cells_y < 1) return;
  auto texel = [&](int i, int j) {
    if (repeat) return map.at(i % map.width, j % map.height);
    return map.at(std::min(i, map.width - 1), std::min(j, map.height - 1));
  };
  start(cells_x, cells_y,
        "the min-depth pyramid of a " + std::to_string(map.width) + "x" + std::to_string(map.height) +
            " depth map");
  for (int j = 0; j < cells_y; ++j)
    for (int i = 0; i < cells_x; ++i)
      min_depth_[std::size_t(j) * std::size_t(cells_x) + std::size_t(i)] =
          std::min({texel(i, j), texel(i + 1, j), texel(i, j + 1), texel(i + 1, j + 1)});
  reduce(repeat);
}

MinDepthPyramid::MinDepthPyramid(int cells_x, int cells_y, Wrap wrap, const std::vector<float>& cells) {
  if (cells_x < 1 || cells_y < 1) return;
  if (cells.size() != std::size_t(cells_x) * std::size_t(cells_y))
    throw std::logic_error("MinDepthPyramid: level 0 is not cells_x x cells_y");
  start(cells_x, cells_y,
        "a min-depth pyramid over " + std::to_string(cells_x) + "x" + std::to_string(cells_y) + " cells");
  std::copy(cells.begin(), cells.end(), min_depth_.begin());
  reduce(wrap == Wrap::repeat);
}

GlImage MinDepthPyramid::gl_image() const {
  const int last = levels() - 1;
  const std::size_t entries =
      last < 0 ? 1 : std::size_t(offsets_.back()) + std::size_t(blocks_x(last)) * std::size_t(blocks_y(last));
  const std::size_t rows = (entries + kGlAtlasWidth - 1) / kGlAtlasWidth;
  GlImage image;
  image.width = kGlAtlasWidth;
  image.height = int(rows);
  image.texels.assign(rows * kGlAtlasWidth, 1.0f);
  if (last >= 0) std::copy(data(), data() + entries, image.texels.begin());
  image.uniforms = {{"pyramidAtlasWidth", {kGlAtlasWidth}},
                    {"pyramidLevels", {levels()}},
                    {"levelOffsets", offsets_},
                    {"levelBlocksX", blocks_x_}};
  return image;
}

}  // namespace heightmarch
