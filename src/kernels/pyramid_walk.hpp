#pragma once
// The min-depth pyramid walk of maximum-mipmap tracing (Tevs, Ihrke and Seidel 2008; Drobot's
// quadtree displacement mapping is the same walk): the ray goes down the min-depth pyramid while it
// may touch a block's shallowest texel and back up after it leaves a block's parent without a hit;
// in a cell it may touch, it tests the bilinear patch's quadratic in float.
//
// In texel space x = u W - 0.5 the ray is x(t) = x0 + dx t at depth t (dx = -s V.x / V.z W), as
// in the exact reference, whose double walk (src/exact/exact_intersector.cpp) takes the same
// steps. Cells and blocks are held as integer-valued floats (exact below 2^24). A sample is one
// texel read: one per pyramid entry, four per tested cell.
//
// Two users: the maxmip technique (techniques/maxmip.hpp) and, made conservative, the exact
// reference's float pass (src/exact/exact_bound.hpp).
#include <algorithm>
#include <limits>

#include "heightmarch/min_depth_pyramid.hpp"
#include "kernels/kernel_context.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The cell a coordinate lies in; on a cell boundary, a path moving towards -x is in the left one.
template <int W>
vfloat<W> floor_to_cell(vfloat<W> x, vfloat<W> rate) {
  const vfloat<W> f = floor(x);
  return select((!(f != x)) & (rate < vfloat<W>(0.0f)), f - vfloat<W>(1.0f), f);
}

// A cell (or block) index wrapped into [0, n - 1] (REPEAT), in float as the sampler wraps.
template <int W>
vfloat<W> wrap_cell(vfloat<W> c, vfloat<W> n, vfloat<W> inv_n) {
  using F = vfloat<W>;
  F r = c - n * floor(c * inv_n);
  r = select(r < F(0.0f), r + n, r);
  r = select(r >= n, r - n, r);
  return min(max(r, F(0.0f)), n - F(1.0f));
}

// Whether c0 + c1 s + c2 s^2 (c0: the path's depth minus the patch's at the cell entry) reaches
// 0 in [0, span]: at an end, or (concave) at its vertex inside the span. No division: the root
// itself is only needed once per ray (first_root).
template <int W>
vbool<W> reaches_patch(vfloat<W> c0, vfloat<W> c1, vfloat<W> c2, vfloat<W> span) {
  using F = vfloat<W>;
  const F zero(0.0f);
  const vbool<W> ends_below = c0 + span * (c1 + span * c2) >= zero;
  const vbool<W> vertex_inside = (c2 < zero) & (c1 > zero) & (c1 < (zero - F(2.0f) * c2) * span);
  return (c0 >= zero) | ends_below | (vertex_inside & (c1 * c1 - F(4.0f) * c2 * c0 >= zero));
}

// The first root in [0, span] of c0 + c1 s + c2 s^2, for a cell reaches_patch() accepted:
// 0 when it starts at or below the patch, else the crossing (clamped into the span, where
// rounding put it outside).
template <int W>
vfloat<W> first_root(vfloat<W> c0, vfloat<W> c1, vfloat<W> c2, vfloat<W> span) {
  using F = vfloat<W>;
  const F zero(0.0f);
  const vbool<W> linear = !(abs(c2) * span > F(1e-6f) * (abs(c1) + abs(c0) / max(span, F(1e-30f))));
  const F root_disc = sqrt(max(c1 * c1 - F(4.0f) * c2 * c0, zero));
  const F q = F(-0.5f) * (c1 + select(c1 < zero, zero - root_disc, root_disc));
  const F r1 = q / c2, r2 = c0 / q;
  // c0 < 0: a concave patch's crossing is its smaller root (both are positive), a convex one's
  // the positive root.
  const F quadratic = select(min(r1, r2) >= zero, min(r1, r2), max(r1, r2));
  const F root = select(linear, (zero - c0) / c1, quadratic);
  return select(c0 >= zero, zero, min(max(root, zero), span));
}

// The four texels of cell (cx, cy) (CLAMP's edge cells repeat the edge texels).
template <Addressing ADDRESSING, int W>
void cell_texels(const KernelTexture& texture, vfloat<W> cx, vfloat<W> cy, vfloat<W>& t00, vfloat<W>& t10,
                 vfloat<W>& t01, vfloat<W>& t11) {
  using F = vfloat<W>;
  using I = vint<W>;
  constexpr bool kRepeat = ADDRESSING != Addressing::clamp;
  const F width(float(texture.width)), height(float(texture.height));
  const F wx = kRepeat ? wrap_cell(cx, width, F(1.0f / float(texture.width))) : max(cx, F(0.0f));
  const F wy = kRepeat ? wrap_cell(cy, height, F(1.0f / float(texture.height))) : max(cy, F(0.0f));
  const I ix = min(to_int(wx), I(texture.width - 1)), iy = min(to_int(wy), I(texture.height - 1));
  const I index = iy * I(texture.stride) + ix;
  gather_pairs(texture.texels, index, t00, t10);
  gather_pairs(texture.texels + texture.stride, index, t01, t11);
  if constexpr (!kRepeat) {
    t10 = select(cx < F(0.0f), t00, t10);
    t11 = select(cx < F(0.0f), t01, t11);
    t01 = select(cy < F(0.0f), t00, t01);
    t11 = select(cy < F(0.0f), t10, t11);
  }
}

// The walk's outcome per lane: the depth at which it entered the cell it stopped in (or, cut
// off by the bound, the depth it had cleared), and that cell's quadratic over its span.
template <int W>
struct PyramidWalk {
  vfloat<W> t;
  vfloat<W> cx, cy;              // the cell it stopped in
  vfloat<W> c0, c1, c2, span;    // its quadratic (not kept by the conservative walk)
  vfloat<W> t00, t10, t01, t11;  // its texels (kept by the conservative walk only)
  vbool<W> reached;  // stopped in a cell it may touch
  vbool<W> cut_off;  // stopped by the bound on passes
  vint<W> samples;
};

// CONSERVATIVE (the exact reference's float pass): every test is loosened by a margin eta that
// bounds the walk's rounding, so that a lane stops no later than the first cell the exact path
// touches (docs/conventions.md, the exact intersection).
template <bool CONSERVATIVE, int W, Addressing ADDRESSING>
PyramidWalk<W> walk_pyramid(KernelContext<W, ADDRESSING>& k, vfloat<W> x0, vfloat<W> y0, vfloat<W> dx,
                            vfloat<W> dy, vfloat<W> eta) {
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  constexpr bool kRepeat = ADDRESSING != Addressing::clamp;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const KernelTexture& texture = k.texture;
  const F width(float(texture.width)), height(float(texture.height));
  const F inv_width(1.0f / float(texture.width)), inv_height(1.0f / float(texture.height));
  const int top = texture.min_depth_pyramid.levels - 1;  // -1: no interior cell (CLAMP, one texel wide)
  const I top_level(top < 0 ? 0 : top);
  const auto clamp_cell = [&](F c, F n) { return kRepeat ? c : min(max(c, F(-1.0f)), n - F(1.0f)); };

  // A path parallel to an axis (dx = +0: the callers compute 0 - p, never -0) exits on the
  // high side at infinity.
  const B high_x = !(dx < F(0.0f)), high_y = !(dy < F(0.0f));
  const F inv_dx = F(1.0f) / dx, inv_dy = F(1.0f) / dy;

  PyramidWalk<W> walk;
  walk.t = F(0.0f);
  walk.c0 = walk.c1 = walk.c2 = walk.span = F(0.0f);
  walk.t00 = walk.t10 = walk.t01 = walk.t11 = F(0.0f);
  walk.reached = !B::all_true();
  walk.samples = I(0);
  F& t = walk.t;
  F cx = clamp_cell(floor_to_cell(x0, dx), width), cy = clamp_cell(floor_to_cell(y0, dy), height);
  // Start where a block is about an eighth of the path's extent: the levels above it would
  // almost always be descended again, those below it climbed.
  const F extent = abs(dx) + abs(dy);
  I level(0);
  for (int l = 1; l <= top; ++l) level = select(extent >= F(float(1 << (l + 3))), I(l), level);
  // Per level: where its entries start (MinDepthPyramid's layout), its blocks a side
  // (ceil(cells / 2^L)), 2^L and 2^-L, looked up by each lane's level (register permutes where
  // the ISA has them) rather than carried along in selects at every change of level.
  static_assert(MinDepthPyramid::kMaxLevels <= 16, "the per-level tables are Table16s");
  Table16<std::int32_t> level_offset, level_blocks_x;
  Table16<float> level_size, level_inv_size;
  const int last_cell_x = kRepeat ? texture.width - 1 : texture.width - 2;
  for (int l = 0; l <= std::max(top, 0); ++l) {
    level_offset.values[l] = top < 0 ? 0 : texture.min_depth_pyramid.level_offsets[l];
    level_blocks_x.values[l] = (last_cell_x >> l) + 1;
    level_size.values[l] = float(1 << l);
    level_inv_size.values[l] = 1.0f / float(1 << l);
  }
  B active = B::all_true();
  // Each pass advances t or descends a level: the cells on the path times the levels bound it.
  const F lane_bound = F(float(2 * (top + 2))) * (extent + F(2.0f));
  F pass(0.0f);
  B cut_off = !B::all_true();
  constexpr int kMaxPasses = 1 << 25;
  for (int p = 0; p < kMaxPasses && any(active); ++p) {
    pass = pass + F(1.0f);
    // Past its bound a lane stops where it is, its path clear down to t (cut off).
    const B over = active & (pass > lane_bound);
    cut_off = cut_off | over;
    active = active & !over;
    B interior = B::all_true();
    if constexpr (!kRepeat)
      interior = (cx >= F(0.0f)) & (cx < width - F(1.0f)) & (cy >= F(0.0f)) & (cy < height - F(1.0f));
    const B in_pyramid = active & interior & (top >= 0 ? B::all_true() : !B::all_true());
    const F size = lookup(level_size, level), inv_size = lookup(level_inv_size, level);

    // The lane's box: its block at its level (blocks tile the period: REPEAT keeps a level only
    // while 2^L divides both sides), or (CLAMP edge cells) the cell, infinite on its outer side.
    const F bx_unwrapped = floor(cx * inv_size), by_unwrapped = floor(cy * inv_size);
    F x_lo = bx_unwrapped * size, y_lo = by_unwrapped * size;
    F x_hi = x_lo + size, y_hi = y_lo + size;
    if constexpr (!kRepeat) {
      x_hi = min(x_hi, width - F(1.0f));
      y_hi = min(y_hi, height - F(1.0f));
      x_lo = select(interior, x_lo, select(cx < F(0.0f), F(-kInf), cx));
      x_hi = select(interior, x_hi, select(cx >= width - F(1.0f), F(kInf), cx + F(1.0f)));
      y_lo = select(interior, y_lo, select(cy < F(0.0f), F(-kInf), cy));
      y_hi = select(interior, y_hi, select(cy >= height - F(1.0f), F(kInf), cy + F(1.0f)));
    }
    const F tx = (select(high_x, x_hi, x_lo) - x0) * inv_dx, ty = (select(high_y, y_hi, y_lo) - y0) * inv_dy;
    const F te = min(tx, ty);
    const F t_end = min(te, F(1.0f));

    F shallowest(-kInf);
    if (top >= 0) {
      // The block's entry; REPEAT wraps the block index into the level's nb blocks a side.
      F bx = bx_unwrapped, by = by_unwrapped;
      if constexpr (kRepeat) {
        const F nbx = width * inv_size, nby = height * inv_size;
        if constexpr (ADDRESSING == Addressing::repeat_pow2) {  // exact in float: no correction
          bx = bx - nbx * floor(bx * inv_width * size);
          by = by - nby * floor(by * inv_height * size);
        } else {
          bx = wrap_cell(bx, nbx, inv_width * size);
          by = wrap_cell(by, nby, inv_height * size);
        }
      }
      const I entry = lookup(level_offset, level) + to_int(by) * lookup(level_blocks_x, level) + to_int(bx);
      if constexpr (!CONSERVATIVE) k.count(in_pyramid, walk.samples, 1);
      shallowest = select(in_pyramid, gather(texture.min_depth_pyramid.texels, select(in_pyramid, entry, I(0))), F(-kInf));
    }
    const F clear_above = shallowest - eta;  // the path is clear of the block above this depth
    const B skip = in_pyramid & (t_end < clear_above);
    const B descend = in_pyramid & (!skip) & (I(0) < level);
    const B solve = active & (!skip) & (!descend);

    B hit = !B::all_true();
    if (any(solve)) {
      F t00, t10, t01, t11;
      cell_texels<ADDRESSING>(texture, cx, cy, t00, t10, t01, t11);
      k.count(solve, walk.samples, CONSERVATIVE ? 1 : 4);
      const F fx = (x0 - cx) + dx * t, fy = (y0 - cy) + dy * t;
      const F e = t10 - t00, f = t01 - t00, g = (t11 - t10) - (t01 - t00);
      const F c0 = t - (t00 + e * fx + f * fy + g * fx * fy) + eta;
      const F c1 = F(1.0f) - (e * dx + f * dy + g * (fx * dy + fy * dx));
      const F c2 = F(0.0f) - g * dx * dy;
      const F span = t_end - t;
      hit = solve & reaches_patch(c0, c1, c2, span);
      if constexpr (CONSERVATIVE) {  // the exact reference solves the cell again in double
        walk.t00 = select(hit, t00, walk.t00);
        walk.t10 = select(hit, t10, walk.t10);
        walk.t01 = select(hit, t01, walk.t01);
        walk.t11 = select(hit, t11, walk.t11);
      } else {
        walk.c0 = select(hit, c0, walk.c0);
        walk.c1 = select(hit, c1, walk.c1);
        walk.c2 = select(hit, c2, walk.c2);
        walk.span = select(hit, span, walk.span);
      }
      walk.reached = walk.reached | hit;
      active = active & !hit;
    }

    // Leaving the box without a hit: no hit at all past depth 1, else into the next box.
    // Descending: nothing in the block is met before the path reaches its shallowest depth.
    const B leave = skip | (solve & !hit);
    const B beyond = leave & !(te < F(1.0f));
    active = active & !beyond;
    const B move = leave & !beyond;
    const B reach = descend & (clear_above > t);
    const F t_next = select(move, te, min(clear_above, t_end));
    const F at_x = min(max(floor_to_cell(x0 + dx * t_next, dx), x_lo), x_hi - F(1.0f));
    const F at_y = min(max(floor_to_cell(y0 + dy * t_next, dy), y_lo), y_hi - F(1.0f));
    const B exit_x = move & !(tx > ty), exit_y = move & !(ty > tx);
    const B step = move | reach;
    t = select(step, t_next, t);
    cx = select(step, clamp_cell(select(exit_x, select(high_x, x_hi, x_lo - F(1.0f)), at_x), width), cx);
    cy = select(step, clamp_cell(select(exit_y, select(high_y, y_hi, y_lo - F(1.0f)), at_y), height), cy);

    // Up a level only out of the block's parent: inside it the parent would be descended again.
    // The parent changes where the crossed side lies on a multiple of twice the block's side.
    const F half_inv = inv_size * F(0.5f);
    const F side_x = select(high_x, x_hi, x_lo) * half_inv, side_y = select(high_y, y_hi, y_lo) * half_inv;
    const B new_parent = (exit_x & !(floor(side_x) != side_x)) | (exit_y & !(floor(side_y) != side_y));
    const B up = move & new_parent & (level < top_level);
    level = select(up, level + I(1), select(descend, level - I(1), level));
  }
  walk.cut_off = cut_off | active;
  walk.cx = cx;
  walk.cy = cy;
  return walk;
}

// A ray's path: P = s V.xy / V.z, its uv offset per unit depth (as the layered techniques'), and
// in texel space its start (x0, y0) and its offset per unit depth (dx, dy).
template <int W>
struct TexelPath {
  vfloat<W> p_x, p_y, x0, y0, dx, dy;
};

template <int W, Addressing ADDRESSING>
TexelPath<W> texel_path(const KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  TexelPath<W> path;
  path.p_x = ray.vx / ray.vz * F(k.params.scale);
  path.p_y = ray.vy / ray.vz * F(k.params.scale);
  const F width(float(k.texture.width)), height(float(k.texture.height));
  path.x0 = ray.tx * width - F(0.5f);
  path.y0 = ray.ty * height - F(0.5f);
  path.dx = F(0.0f) - path.p_x * width;
  path.dy = F(0.0f) - path.p_y * height;
  return path;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
