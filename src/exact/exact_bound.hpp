#pragma once
// The exact reference's float pass (ExactReference, src/exact/exact_hits.cpp): the pyramid walk
// of kernels/pyramid_walk.hpp made conservative, then the cell it stopped in solved in double,
// D lanes at a time, with the double walk's own code (cell_quadratic.hpp). Compiled per ISA into
// the kernel table (src/isa/kernel_table.hpp) like a technique.
#include <limits>

#include "exact/cell_quadratic.hpp"
#include "kernels/pyramid_walk.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The exact reference's float pass: the walk with every test loosened by eta, which bounds what
// float rounding can change. The walk's positions, exit times and cell offsets are within a few
// ulps of their exact values: ulps of the texel coordinates (|x0| + |y0|: the origin, the cell a
// point falls in near a side) and of the path's extent (|dx| + |dy|: exit times, slopes,
// products; about 1.5 and 11 ulps per axis, counting each rounding at its worst). The bilinear
// surface (texels in [0, 1]) changes by at most |a| + |b| for a move of (a, b) texels, so these
// become depth errors of the same size; eta is at least 5 times their sum (docs/conventions.md,
// the exact intersection). The lane stops in a cell (depth: its entry) no
// later than the first cell the exact path touches, or (depth 1) shows the path clear to depth 1.
template <int W>
vfloat<W> exact_margin(const TexelPath<W>& path) {
  using F = vfloat<W>;
  return F(0x1p-20f) * (abs(path.x0) + abs(path.y0)) + F(0x1p-18f) * (abs(path.dx) + abs(path.dy) + F(4.0f));
}

// The conservative walk of each ray of the packet, queued.
template <int W, Addressing ADDRESSING>
void queue_exact_bound(const KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray, WalkQueue& queue,
                       int i) {
  const TexelPath<W> path = texel_path(k, ray);
  queue_walk(k, path.x0, path.y0, path.dx, path.dy, exact_margin(path), queue, i);
}

// The packet's outcome from its conservative walks.
template <int W, Addressing ADDRESSING>
HitPacket<W> maxmip_exact_bound(KernelContext<W, ADDRESSING>& k, const RayPacket<W>& ray,
                                const PyramidWalk<W>& walk) {
  using F = vfloat<W>;
  const TexelPath<W> path = texel_path(k, ray);
  const F &dx = path.dx, &dy = path.dy;
  const F eta = exact_margin(path);
  // Where the walk stopped past 0 it had shown depth - D < -eta + (its rounding, < eta / 2);
  // depth - D changes by at most 1 + |dx| + |dy| per unit depth, so the path is clear a little
  // further, nu: far enough that the double walk starts in the cell the pass stopped in, not at
  // the end of the one before (where it would solve a cell again).
  const F nu = eta / (F(2.0f) * (F(1.0f) + abs(dx) + abs(dy)));
  const F clear = select(walk.t > F(0.0f), min(walk.t + nu, F(1.0f)), walk.t);  // D <= 1: a hit by 1
  const F from = select(walk.reached | walk.cut_off, clear, F(1.0f));

  // The double walk would start in the cell at `from` and solve it first: that step in double, D
  // lanes at a time, with the walk's own code (src/exact/cell_quadratic.hpp) and the texels the
  // pass already read, where that cell is the one the pass stopped in. A lane whose cell crosses
  // there is final (settled: the exact hit). Where it shows the path clear through that cell
  // (the margin's false alarms: most of the rest), the next cell the path enters is solved too,
  // as the walk's step at level 0 goes: its first crossing there is the first of the path. The
  // others (a root rounding hid, another cell, no crossing in either) go on in the double walk
  // from `from` (not settled; clear_depth = `from`).
  alignas(64) float lane_tx[W], lane_ty[W], lane_vx[W], lane_vy[W], lane_vz[W], lane_from[W], lane_cx[W],
      lane_cy[W], lane_reached[W], t00[W], t10[W], t01[W], t11[W];
  alignas(64) float out_u[W], out_v[W], out_depth[W], out_final[W];
  alignas(64) float next[W], next_cx[W], next_cy[W], in_next[W];  // the next cell's lanes
  alignas(64) double next_t[W];
  // Until settled: not final, at `from`.
  ray.tx.store(out_u);
  ray.ty.store(out_v);
  from.store(out_depth);
  F(0.0f).store(out_final);
  F(0.0f).store(in_next);
  ray.tx.store(lane_tx);
  ray.ty.store(lane_ty);
  ray.vx.store(lane_vx);
  ray.vy.store(lane_vy);
  ray.vz.store(lane_vz);
  from.store(lane_from);
  walk.cx.store(lane_cx);
  walk.cy.store(lane_cy);
  select(walk.reached, F(1.0f), F(0.0f)).store(lane_reached);
  walk.t00.store(t00);
  walk.t10.store(t10);
  walk.t01.store(t01);
  walk.t11.store(t11);
  constexpr int D = W < kDoubleWidth ? W : kDoubleWidth;
  using Dv = vdouble<D>;
  using Dm = vboold<D>;
  constexpr bool kRepeat = ADDRESSING != Addressing::clamp;
  constexpr double kFar = double(std::numeric_limits<long long>::max() / 4);  // first_hit's CLAMP edge
  const Dv w(double(k.texture.width)), h(double(k.texture.height)), s(double(k.params.scale));
  const Dv zero(0.0), one(1.0), inf(std::numeric_limits<double>::infinity());
  // Lanes l .. l + D - 1's path, as ExactIntersector::intersect makes it.
  struct DoublePath {
    Dv tx, ty, vx, vy, offset_per_depth, px, py, pdx, pdy;
  };
  const auto path_at = [&](int l) {
    DoublePath p;
    p.tx = Dv::load(lane_tx + l);
    p.ty = Dv::load(lane_ty + l);
    p.vx = Dv::load(lane_vx + l);
    p.vy = Dv::load(lane_vy + l);
    p.offset_per_depth = s / Dv::load(lane_vz + l);
    p.px = p.tx * w - Dv(0.5);
    p.py = p.ty * h - Dv(0.5);
    p.pdx = -(p.offset_per_depth * p.vx) * w;
    p.pdy = -(p.offset_per_depth * p.vy) * h;
    return p;
  };
  // Cell (ci, cj) entered at t0, solved as first_hit's step at level 0: where the path leaves it
  // along each axis (CLAMP's edge cells reach to infinity outside) and its first crossing.
  struct CellStep {
    Dv exit_x, exit_y, te, s;  // s: the crossing, from t0
    Dm crosses, hidden;        // first_crossing's
  };
  const auto solve_cell = [&](const DoublePath& p, Dv ci, Dv cj, Dv t0, const float* texels_00,
                              const float* texels_10, const float* texels_01, const float* texels_11, int l) {
    Dv x_lo = ci, x_hi = ci + one, y_lo = cj, y_hi = cj + one;
    if constexpr (!kRepeat) {
      x_lo = select(ci == -one, Dv(-kFar), x_lo);
      x_hi = select(ci == w - one, Dv(kFar), x_hi);
      y_lo = select(cj == -one, Dv(-kFar), y_lo);
      y_hi = select(cj == h - one, Dv(kFar), y_hi);
    }
    const Dv inv_dx = one / p.pdx, inv_dy = one / p.pdy;
    CellStep step;
    step.exit_x =
        select(p.pdx > zero, (x_hi - p.px) * inv_dx, select(p.pdx < zero, (x_lo - p.px) * inv_dx, inf));
    step.exit_y =
        select(p.pdy > zero, (y_hi - p.py) * inv_dy, select(p.pdy < zero, (y_lo - p.py) * inv_dy, inf));
    step.te = max(t0, min(step.exit_x, step.exit_y));
    const CellQuadratic<Dv> q =
        cell_quadratic(Dv::load(texels_00 + l), Dv::load(texels_10 + l), Dv::load(texels_01 + l),
                       Dv::load(texels_11 + l), ci, cj, p.px, p.py, p.pdx, p.pdy, zero, one, t0);
    const CellCrossing<Dv> crossing = first_crossing(q, min(step.te, one) - t0);
    step.s = crossing.s;
    step.crosses = crossing.crosses;
    step.hidden = crossing.hidden;
    return step;
  };
  const auto clamp_cell = [&](Dv c, Dv n) { return kRepeat ? c : min(max(c, -one), n - one); };
  // The final lanes' hit at depth d.
  const auto settle = [&](const DoublePath& p, Dm final, Dv d, int l) {
    select(final, one, Dv::load(out_final + l)).store(out_final + l);
    select(final, d, Dv::load(out_depth + l)).store(out_depth + l);
    select(final, p.tx - d * p.offset_per_depth * p.vx, Dv::load(out_u + l)).store(out_u + l);
    select(final, p.ty - d * p.offset_per_depth * p.vy, Dv::load(out_v + l)).store(out_v + l);
  };
  for (int l = 0; l < W; l += D) {
    const DoublePath p = path_at(l);
    const Dv t0 = Dv::load(lane_from + l);
    // The cell first_hit starts in.
    const Dv xt = p.px + p.pdx * t0, yt = p.py + p.pdy * t0;
    Dv ci = floor(xt), cj = floor(yt);
    ci = clamp_cell(select((ci == xt) & (p.pdx < zero), ci - one, ci), w);
    cj = clamp_cell(select((cj == yt) & (p.pdy < zero), cj - one, cj), h);
    const CellStep step = solve_cell(p, ci, cj, t0, t00, t10, t01, t11, l);
    const Dm same_cell =
        (Dv::load(lane_reached + l) != zero) & (ci == Dv::load(lane_cx + l)) & (cj == Dv::load(lane_cy + l));
    settle(p, same_cell & step.crosses, t0 + step.s, l);
    // Clear through the cell, and not at depth 1 on leaving it: across the side(s) it leaves by.
    const Dm go_on = same_cell & !(step.crosses | step.hidden) & (step.te < one);
    const Dv across_x = select(p.pdx > zero, ci + one, ci - one);
    const Dv across_y = select(p.pdy > zero, cj + one, cj - one);
    select(go_on, one, zero).store(next + l);
    select(go_on & (step.exit_x <= step.exit_y), clamp_cell(across_x, w), ci).store(next_cx + l);
    select(go_on & (step.exit_y <= step.exit_x), clamp_cell(across_y, h), cj).store(next_cy + l);
    step.te.store(next_t + l);
  }
  if (any(F::load(next) != F(0.0f))) {
    const F cx = F::load(next_cx), cy = F::load(next_cy);
    F n00, n10, n01, n11;
    cell_texels<ADDRESSING>(k.texture, to_int(cx), to_int(cy), n00, n10, n01, n11);
    n00.store(t00);
    n10.store(t10);
    n01.store(t01);
    n11.store(t11);
    for (int l = 0; l < W; l += D) {
      const Dm wanted = Dv::load(next + l) != zero;
      if (!any(wanted)) continue;  // about half the chunks on waves: a tenth of the lanes go on
      const DoublePath p = path_at(l);
      const Dv t0 = Dv::load(next_t + l);
      const CellStep step =
          solve_cell(p, Dv::load(next_cx + l), Dv::load(next_cy + l), t0, t00, t10, t01, t11, l);
      const Dm final = wanted & step.crosses;
      settle(p, final, t0 + step.s, l);
      select(final, one, zero).store(in_next + l);
    }
  }
  HitPacket<W> out;
  out.u = F::load(out_u);
  out.v = F::load(out_v);
  out.depth = F::load(out_depth);
  out.settled = select(F::load(out_final) != F(0.0f), vint<W>(1), vint<W>(0));
  out.clear_depth = from;
  // A cell solved in double is a sample; the first's the caller counts (as the double walk's).
  out.samples = walk.samples + select(F::load(in_next) != F(0.0f), vint<W>(1), vint<W>(0));
  return out;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
