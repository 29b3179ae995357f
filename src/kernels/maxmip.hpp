#pragma once
// Maximum-mipmap tracing (Tevs, Ihrke and Seidel 2008; Drobot's quadtree displacement mapping
// is the same walk): the ray goes down the min-depth pyramid while it may touch a block's
// shallowest texel and back up after each block it leaves without a hit; in a cell it may touch,
// it solves the bilinear patch's quadratic in float. Exact up to float rounding, at a cost that
// grows with the depth features on the ray, not with the resolution.
//
// In texel space x = u W - 0.5 the ray is x(t) = x0 + dx t at depth t (dx = -s V.x / V.z W), as
// in the exact reference, whose double walk this mirrors lane by lane. Cells and blocks are held
// as integer-valued floats (exact below 2^24). A sample is one texel read: one per pyramid entry,
// four per solved cell.
#include <limits>

#include "kernels/kernel_context.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The cell a coordinate lies in; on a cell boundary, a path moving towards -x is in the left one.
template <int W>
vfloat<W> floor_to_cell(vfloat<W> x, vfloat<W> rate) {
  const vfloat<W> f = floor(x);
  return select(!(f != x) & (rate < vfloat<W>(0.0f)), f - vfloat<W>(1.0f), f);
}

// t at which x0 + rate t leaves [lo, hi]; infinite for a path parallel to the axis.
template <int W>
vfloat<W> exit_t(vfloat<W> x0, vfloat<W> rate, vfloat<W> inv_rate, vfloat<W> lo, vfloat<W> hi) {
  using F = vfloat<W>;
  const F t = (select(rate > F(0.0f), hi, lo) - x0) * inv_rate;
  return select((rate > F(0.0f)) | (rate < F(0.0f)), t, F(std::numeric_limits<float>::infinity()));
}

// A cell index wrapped into [0, n - 1] (REPEAT), in float as the sampler wraps.
template <int W>
vfloat<W> wrap_cell(vfloat<W> c, vfloat<W> n, vfloat<W> inv_n) {
  using F = vfloat<W>;
  F r = c - n * floor(c * inv_n);
  r = select(r < F(0.0f), r + n, r);
  r = select(r >= n, r - n, r);
  return min(max(r, F(0.0f)), n - F(1.0f));
}

// The first root in [0, span] of c0 + c1 s + c2 s^2 with c0 < 0, where the path crosses into the
// patch; `found` when there is one or rounding hid it (the path ends the cell at or below).
template <int W>
vfloat<W> first_crossing(vfloat<W> c0, vfloat<W> c1, vfloat<W> c2, vfloat<W> span, vbool<W>& found) {
  using F = vfloat<W>;
  const F zero(0.0f);
  const vbool<W> linear = !(abs(c2) * span > F(1e-6f) * (abs(c1) + abs(c0) / max(span, F(1e-30f))));
  const F disc = c1 * c1 - F(4.0f) * c2 * c0;
  const F root_disc = sqrt(max(disc, zero));
  const F q = F(-0.5f) * (c1 + select(c1 < zero, zero - root_disc, root_disc));
  const F r1 = q / c2, r2 = c0 / q;
  const F first = min(r1, r2), second = max(r1, r2);
  const vbool<W> quadratic = (!linear) & (disc >= zero);
  const vbool<W> in_first = quadratic & (first >= zero) & !(first > span);
  const vbool<W> in_second = quadratic & (second >= zero) & !(second > span);
  const F r_linear = (zero - c0) / c1;
  const vbool<W> in_linear = linear & (c1 > zero) & (r_linear >= zero) & !(r_linear > span);
  const vbool<W> ends_below = c0 + span * (c1 + span * c2) >= zero;
  found = in_first | in_second | in_linear | ends_below;
  return select(in_first, first, select(in_second, second, select(in_linear, r_linear, span)));
}

template <int W, Addressing ADDRESSING>
HitPacket<W> maxmip(KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray) {
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  constexpr bool kRepeat = ADDRESSING != Addressing::clamp;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const KernelTexture& texture = k.texture;
  const F width(float(texture.width)), height(float(texture.height));
  const F inv_width(1.0f / float(texture.width)), inv_height(1.0f / float(texture.height));
  const int top = texture.pyramid_levels - 1;  // -1: no interior cell (CLAMP, one texel wide)
  const I top_level(top < 0 ? 0 : top);

  // uv offset per unit depth, as the layered techniques' P; the path in texel space.
  const F p_x = ray.vx / ray.vz * F(k.params.scale);
  const F p_y = ray.vy / ray.vz * F(k.params.scale);
  const F x0 = ray.tx * width - F(0.5f), y0 = ray.ty * height - F(0.5f);
  const F dx = F(0.0f) - p_x * width, dy = F(0.0f) - p_y * height;
  const F inv_dx = F(1.0f) / dx, inv_dy = F(1.0f) / dy;
  const auto clamp_cell = [&](F c, F n) { return kRepeat ? c : min(max(c, F(-1.0f)), n - F(1.0f)); };

  F t(0.0f), hit_t(1.0f);
  F cx = clamp_cell(floor_to_cell(x0, dx), width), cy = clamp_cell(floor_to_cell(y0, dy), height);
  I level = top_level;
  F size(float(1 << (top < 0 ? 0 : top))), inv_size(1.0f / float(1 << (top < 0 ? 0 : top)));
  I samples(0);
  B active = B::all_true();
  // Each pass advances t or descends a level: the cells on the path times the levels bound it.
  const F lane_bound = F(float(2 * (top + 2))) * (abs(dx) + abs(dy) + F(2.0f));
  F pass(0.0f);
  constexpr int kMaxPasses = 1 << 25;
  for (int p = 0; p < kMaxPasses && any(active); ++p) {
    pass = pass + F(1.0f);
    active = active & !(pass > lane_bound);
    const F wx = kRepeat ? wrap_cell(cx, width, inv_width) : max(cx, F(0.0f));
    const F wy = kRepeat ? wrap_cell(cy, height, inv_height) : max(cy, F(0.0f));
    B interior = B::all_true();
    if constexpr (!kRepeat)
      interior = (cx >= F(0.0f)) & (cx < width - F(1.0f)) & (cy >= F(0.0f)) & (cy < height - F(1.0f));
    const B in_pyramid = active & interior & (top >= 0 ? B::all_true() : !B::all_true());

    // The lane's box: its block at its level, or (CLAMP edge cells) the cell itself, infinite
    // on its outer side.
    const F bx = floor(wx * inv_size), by = floor(wy * inv_size);
    F x_lo = cx - (wx - bx * size), y_lo = cy - (wy - by * size);
    F x_hi = x_lo + size, y_hi = y_lo + size;
    if constexpr (!kRepeat) {
      x_hi = min(x_hi, width - F(1.0f));
      y_hi = min(y_hi, height - F(1.0f));
      x_lo = select(interior, x_lo, select(cx < F(0.0f), F(-kInf), cx));
      x_hi = select(interior, x_hi, select(cx >= width - F(1.0f), F(kInf), cx + F(1.0f)));
      y_lo = select(interior, y_lo, select(cy < F(0.0f), F(-kInf), cy));
      y_hi = select(interior, y_hi, select(cy >= height - F(1.0f), F(kInf), cy + F(1.0f)));
    }
    const F tx = exit_t(x0, dx, inv_dx, x_lo, x_hi), ty = exit_t(y0, dy, inv_dy, y_lo, y_hi);
    const F te = min(tx, ty);
    const F t_end = min(te, F(1.0f));

    F shallowest(-kInf);
    if (top >= 0) {
      const I entry = gather(texture.level_offsets, level) +
                      to_int(by) * gather(texture.level_blocks_x, level) + to_int(bx);
      k.count(in_pyramid, samples, 1);
      shallowest = select(in_pyramid, gather(texture.pyramid, select(in_pyramid, entry, I(0))), F(-kInf));
    }
    const B skip = in_pyramid & (t_end < shallowest);  // the path stays above the block
    const B descend = in_pyramid & (!skip) & (I(0) < level);
    const B solve = active & (!skip) & (!descend);

    B hit = !B::all_true();
    if (any(solve)) {
      // The cell's four texels (CLAMP's edge cells repeat the edge texels), then its quadratic.
      const I ix = min(to_int(wx), I(texture.width - 1)), iy = min(to_int(wy), I(texture.height - 1));
      const I index = iy * I(texture.stride) + ix;
      F t00, t10, t01, t11;
      gather_pairs(texture.texels, index, t00, t10);
      gather_pairs(texture.texels + texture.stride, index, t01, t11);
      k.count(solve, samples, 4);
      if constexpr (!kRepeat) {
        t10 = select(cx < F(0.0f), t00, t10);
        t11 = select(cx < F(0.0f), t01, t11);
        t01 = select(cy < F(0.0f), t00, t01);
        t11 = select(cy < F(0.0f), t10, t11);
      }
      const F fx = (x0 - cx) + dx * t, fy = (y0 - cy) + dy * t;
      const F e = t10 - t00, f = t01 - t00, g = (t11 - t10) - (t01 - t00);
      const F c0 = t - (t00 + e * fx + f * fy + g * fx * fy);
      const F c1 = F(1.0f) - (e * dx + f * dy + g * (fx * dy + fy * dx));
      const F c2 = F(0.0f) - g * dx * dy;
      B found;
      const F root = first_crossing(c0, c1, c2, t_end - t, found);
      const B at_start = !(c0 < F(0.0f));
      hit = solve & (at_start | found);
      hit_t = select(hit, select(at_start, t, t + root), hit_t);
      active = active & !hit;
    }

    // Leaving the box without a hit: no hit at all past depth 1, else into the next box, one
    // level up.
    const B leave = (skip | (solve & !hit));
    const B beyond = leave & !(te < F(1.0f));
    active = active & !beyond;
    const B move = leave & !beyond;
    const F next_x = select(dx > F(0.0f), x_hi, x_lo - F(1.0f));
    const F next_y = select(dy > F(0.0f), y_hi, y_lo - F(1.0f));
    const F at_x = min(max(floor_to_cell(x0 + dx * te, dx), x_lo), x_hi - F(1.0f));
    const F at_y = min(max(floor_to_cell(y0 + dy * te, dy), y_lo), y_hi - F(1.0f));
    F new_cx = clamp_cell(select(!(tx > ty), next_x, at_x), width);
    F new_cy = clamp_cell(select(!(ty > tx), next_y, at_y), height);

    // Descending: nothing in the block is met before the path reaches its shallowest depth.
    const B reach = descend & (shallowest > t);
    const F t_reach = min(shallowest, t_end);
    const F reach_x = min(max(floor_to_cell(x0 + dx * t_reach, dx), x_lo), x_hi - F(1.0f));
    const F reach_y = min(max(floor_to_cell(y0 + dy * t_reach, dy), y_lo), y_hi - F(1.0f));

    t = select(move, te, select(reach, t_reach, t));
    cx = select(move, new_cx, select(reach, reach_x, cx));
    cy = select(move, new_cy, select(reach, reach_y, cy));
    const B up = move & (level < top_level);
    level = select(up, level + I(1), select(descend, level - I(1), level));
    size = select(up, size * F(2.0f), select(descend, size * F(0.5f), size));
    inv_size = select(up, inv_size * F(0.5f), select(descend, inv_size * F(2.0f), inv_size));
  }
  hit_t = select(active, t, hit_t);  // cut off by the bound: the deepest point known clear

  HitPacket<W> out;
  out.u = ray.tx - p_x * hit_t;
  out.v = ray.ty - p_y * hit_t;
  out.depth = hit_t;
  out.samples = samples;
  return out;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
