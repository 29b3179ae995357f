#pragma once
// Trilinear filtering (docs/conventions.md#filters): the depth map's mip chain, built once per map
// as glGenerateMipmap builds one and uploaded level by level to GL so both sides read the same
// floats, and the level of detail GL takes from the gradients of the base texture coordinate.
#include <cmath>
#include <vector>

#include "heightmarch/heightfield.hpp"

namespace heightmarch {

// GL's chain of a W x H texture: levels 0 to floor(log2(max(W, H))), level L of
// max(1, W >> L) x max(1, H >> L) texels. At most 15 (a side of kMaxDepthMapSide).
int mip_level_count(int width, int height);
inline constexpr int kMaxMipLevels = 15;

// Levels 0 (the map) to mip_level_count() - 1, each from the one before by a 2 x 2 box: texel
// (i, j) is (((a + b) + c) + d) * 0.25 of the texels (2i, 2j), (2i + 1, 2j), (2i, 2j + 1) and
// (2i + 1, 2j + 1), summed in the order Mesa's glGenerateMipmap sums them on the CPU. An odd side
// leaves its last column (row) out of the next level, as that code does; a side of 1 reads its one
// column (row) twice. GL's own glGenerateMipmap may filter odd sides otherwise (llvmpipe blits
// with GL_LINEAR), so GL is given these levels, never asked to make its own.
std::vector<DepthMap> build_mip_chain(const DepthMap& map);

// The operations the two templates below are written with, for F = float: the packet types' own
// (found by argument-dependent lookup) pick alike (heightmarch's simd/packet.hpp).
namespace float_ops {
inline float select(bool condition, float a, float b) { return condition ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
}  // namespace float_ops

// log2(x) for x in [1, 2^28] from IEEE operations alone, so that F = float and every packet width
// and ISA give the same bits: the exponent by halvings (exact), then log2 of the mantissa m in
// [sqrt(1/2), sqrt(2)) as the series 2 atanh(s) / ln 2 = 2 / ln 2 (s + s^3 / 3 + ... + s^9 / 9),
// s = (m - 1) / (m + 1). Exact at powers of two; elsewhere within 2e-7 of log2 and the result's rounding
// (tests/mip_chain_test.cpp).
template <class F>
F mip_log2(F x) {
  using float_ops::select;
  F exponent(0.0f);
  for (const int shift : {16, 8, 4, 2, 1}) {
    const auto big = x >= F(std::ldexp(1.0f, shift));
    x = select(big, x * F(std::ldexp(1.0f, -shift)), x);
    exponent = select(big, exponent + F(float(shift)), exponent);
  }
  const auto high = x >= F(1.41421356f);
  x = select(high, x * F(0.5f), x);
  exponent = select(high, exponent + F(1.0f), exponent);
  const F s = (x - F(1.0f)) / (x + F(1.0f));
  const F s2 = s * s;
  // 2 / ((2k + 1) ln 2), k = 0..4
  const F series =
      F(2.88539008f) +
      s2 * (F(0.961796694f) + s2 * (F(0.577078016f) + s2 * (F(0.412198583f) + s2 * F(0.320598898f))));
  return exponent + s * series;
}

// GL's level of detail (OpenGL 4.6, section 8.14.1) of a read whose base texture coordinate moves
// by (du_dx, dv_dx) to the next pixel in x and by (du_dy, dv_dy) in y, on a level 0 of W x H
// texels: lambda = log2 rho, rho = max(|(du_dx W, dv_dx H)|, |(du_dy W, dv_dy H)|), taken as
// log2(rho^2) / 2. Clamped as GL selects levels: lambda <= 0 magnifies (level 0, bilinear), lambda
// >= last_level reads the last level; between, levels floor(lambda) and floor(lambda) + 1 are
// blended by its fraction. Gradients are finite (check_rays); zero ones read level 0. The GLSL
// prelude has its twin (mipLod).
template <class F>
F level_of_detail(F du_dx, F dv_dx, F du_dy, F dv_dy, float width, float height, int last_level) {
  using float_ops::max;
  using float_ops::min;
  const F ux = du_dx * F(width), vx = dv_dx * F(height), uy = du_dy * F(width), vy = dv_dy * F(height);
  const F rho2 = max(ux * ux + vx * vx, uy * uy + vy * vy);
  // log2 on [1, 4^last]: exactly 0 and 2 last at the ends.
  return mip_log2(min(max(rho2, F(1.0f)), F(std::ldexp(1.0f, 2 * last_level)))) * F(0.5f);
}

}  // namespace heightmarch
