#pragma once
// The min-depth pyramid ("maximum mipmap" of heights) over the texel cells of a depth map:
// level 0 holds, per cell (the 2 x 2 texels the bilinear sampler blends between texel centres
// x..x+1, y..y+1 with x = u W - 0.5), the shallowest of its four texels, which bounds the whole
// bilinear patch; level L holds the shallowest of each 2^L x 2^L block of cells. A path whose
// depth stays below a block's entry cannot meet the surface inside it.
//
// REPEAT: cells 0..W-1 wrap; a level exists only while 2^L divides both sides, so blocks tile
// the period. CLAMP: the interior cells 0..W-2; the half-infinite edge cells outside them (where
// the sampler's clamp makes the surface constant along one axis) are left to the caller.
#include <cstdint>
#include <string>
#include <vector>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/sampler.hpp"

namespace heightmarch {

class MinDepthPyramid {
 public:
  static constexpr int kMaxLevels = 16;  // sides up to kMaxDepthMapSide = 2^14 cells

  MinDepthPyramid(const DepthMap& map, Wrap wrap);
  // Over a grid of cells_x x cells_y cells (a map's, as above) whose level 0 is given, `cells` row
  // by row: a bound below some other surface over those cells (the exact reference's of a blend
  // of mip levels, src/exact/filtered_exact.cpp), reduced as the map's is.
  MinDepthPyramid(int cells_x, int cells_y, Wrap wrap, const std::vector<float>& cells);

  int levels() const { return int(offsets_.size()); }  // 0 when the map has no interior cell
  int blocks_x(int level) const { return blocks_x_[std::size_t(level)]; }
  int blocks_y(int level) const { return blocks_y_[std::size_t(level)]; }
  float at(int level, long long bx, long long by) const {
    return min_depth_[std::size_t(offsets_[std::size_t(level)]) +
                      std::size_t(by) * std::size_t(blocks_x(level)) + std::size_t(bx)];
  }

  // The flat layout the packet kernels and the GLSL read: level L's block (bx, by) at
  // offsets()[L] + by * blocks_x()[L] + bx, with blocks_x()[L] = ceil(cells a side / 2^L).
  const float* data() const { return min_depth_.data(); }
  const std::int32_t* offsets() const { return offsets_.data(); }
  const std::int32_t* blocks_x() const { return blocks_x_.data(); }
  const std::int32_t* blocks_y() const { return blocks_y_.data(); }
  std::size_t bytes() const { return min_depth_.size() * sizeof(float); }

  // As the packet kernels read it (KernelTexture's slot), and as the GLSL does: row after row of
  // an R32F atlas kGlAtlasWidth wide (CLAMP's interior cells, W - 1 a side, halve with rounding
  // up, which no GL mip chain holds), read at (i % width, i / width) with texelFetch, with the
  // uniforms pyramidAtlasWidth, pyramidLevels, levelOffsets and levelBlocksX.
  TextureSlot slot() const { return {data(), offsets(), levels()}; }
  static constexpr int kGlAtlasWidth = 4096;
  GlImage gl_image() const;

  double build_seconds = 0;  // set by its builder (build_min_depth_pyramid, precomputed.hpp)

 private:
  void add_level(int blocks_x, int blocks_y);
  void start(int cells_x, int cells_y, const std::string& what);  // level 0, room for the rest
  void reduce(bool repeat);                                       // the levels above level 0

  std::vector<float> min_depth_;
  std::vector<std::int32_t> offsets_, blocks_x_, blocks_y_;
};

}  // namespace heightmarch
