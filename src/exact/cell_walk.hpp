#pragma once
// The double walk of the exact intersection over a surface's texel cells, written once for the
// surfaces it solves: the level-0 bilinear surface (ExactIntersector, exact_intersector.cpp) and
// the trilinear surface a ray reads at its level of detail, a blend of two mip levels
// (FilteredExactReference, filtered_exact.cpp). A Surface says how many cells it has a side,
// whether they repeat, how shallow a block of its min-depth pyramid may be, and solves one cell:
//
//   long long width() const, height() const;  // texels a side (the cells of its grid)
//   bool repeat() const;
//   int top_level() const;                    // its pyramid's last level; -1 without one
//   double shallowest(int level, long long bx, long long by) const;  // a bound below the block
//   bool solve_cell(long long ci, long long cj, const HeightfieldPath& path, double t0, double t1,
//                   double& t_hit) const;     // the first t in [t0, t1] at or below the surface
//
// Internal linkage, as cell_quadratic.hpp: each translation unit keeps its own copy.
#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

#include "exact/cell_quadratic.hpp"
#include "heightmarch/exact.hpp"

namespace heightmarch {
namespace {

inline long long floor_to_cell(double x, double direction) {
  const double f = std::floor(x);
  // On a cell boundary, a path moving towards -x is in the cell on the left.
  return (long long)f - (f == x && direction < 0.0 ? 1 : 0);
}

inline long long wrap_index(long long i, long long n) {
  if ((n & (n - 1)) == 0) return i & (n - 1);  // the common power-of-two side, without a division
  const long long r = i % n;
  return r < 0 ? r + n : r;
}

// Texel (i, j) of a map under its wrap mode.
inline double wrapped_texel(const DepthMap& map, Wrap wrap, long long i, long long j) {
  const long long w = map.width, h = map.height;
  if (wrap == Wrap::repeat) {
    i = wrap_index(i, w);
    j = wrap_index(j, h);
  } else {
    i = std::clamp(i, 0LL, w - 1);
    j = std::clamp(j, 0LL, h - 1);
  }
  return map.at(int(i), int(j));
}

// The ray entering at (tx, ty) with unit V towards the eye, at scale s, as a path through a grid of
// w x h texels (x = u w - 0.5), from depth 0 to 1.
inline HeightfieldPath ray_path(double tx, double ty, double vx, double vy, double vz, double scale, double w,
                                double h) {
  const double offset_per_depth = scale / vz;  // s / V.z: one division for both axes
  return {tx * w - 0.5, ty * h - 0.5, -(offset_per_depth * vx) * w, -(offset_per_depth * vy) * h, 0.0,
          1.0,          1.0};
}

// The first s in [0, span] where a cell's quadratic reaches 0 from below; where rounding hid the
// root (first_crossing's `hidden`), the sign change bisected.
inline bool first_root(const CellQuadratic<double>& q, double span, double& s) {
  const CellCrossing<double> crossing = first_crossing(q, span);
  s = crossing.s;
  if (!crossing.crosses && !crossing.hidden) return false;
  if (crossing.hidden) {  // bisect the sign change
    auto h = [&](double x) { return q.c0 + x * (q.c1 + x * q.c2); };
    double lo = 0.0, hi = span;
    for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (h(mid) >= 0.0 ? hi : lo) = mid;
    }
    s = hi;
  }
  return true;
}

// Smallest t in [from, t_max] with depth(t) >= the surface at (x(t), y(t)). From 0 the walk starts
// high in the pyramid; from a later t (where a float pass stopped, the path clear before it) it
// starts in that cell, which it solves at once.
template <class Surface>
PathHit walk_cells(const Surface& surface, const HeightfieldPath& p, double from) {
  PathHit result;
  const bool repeat = surface.repeat();
  const long long w = surface.width(), h = surface.height();
  auto clamp_cell = [&](long long c, long long n) { return repeat ? c : std::clamp(c, -1LL, n - 1); };
  long long cx = clamp_cell(floor_to_cell(p.x0 + p.dx * from, p.dx), w);
  long long cy = clamp_cell(floor_to_cell(p.y0 + p.dy * from, p.dy), h);
  // t at which the path leaves the cell range [lo, hi) along one axis (hi exclusive).
  // Divisions dominated the walk: each axis' rate is inverted once per path.
  const double inv_dx = 1.0 / p.dx, inv_dy = 1.0 / p.dy;
  auto exit_t = [](double origin, double rate, double inv_rate, long long lo, long long hi) {
    if (rate > 0.0) return (double(hi) - origin) * inv_rate;
    if (rate < 0.0) return (double(lo) - origin) * inv_rate;
    return std::numeric_limits<double>::infinity();
  };
  // A clamp edge cell reaches to infinity on its outer side.
  auto cell_hi = [&](long long c, long long n) { return !repeat && c == n - 1 ? LLONG_MAX / 4 : c + 1; };
  auto cell_lo = [&](long long c) { return !repeat && c == -1 ? -(LLONG_MAX / 4) : c; };
  auto depth = [&](double t) { return p.depth0 + p.ddepth * t; };
  auto interior = [&](long long c, long long n) { return repeat || (c >= 0 && c < n - 1); };
  // Leaving a block of level L across (x_side, y_side), the walk goes up a level only when it
  // also leaves the parent: where the crossed side lies on a multiple of 2^(L + 1).
  auto new_parent = [&](int level, bool across_x, long long x_side, bool across_y, long long y_side) {
    const long long mask = (2LL << level) - 1;
    return (across_x && (x_side & mask) == 0) || (across_y && (y_side & mask) == 0);
  };

  // Tevs et al.'s maximum-mipmap walk: `level` goes down while the path may touch a block's
  // shallowest texel and up after the path leaves a block's parent without a hit, so a pass
  // either advances t or descends. Passes are bounded by the cells on the path times the levels.
  // It starts where a block is about an eighth of the path's extent (the float walk of
  // src/kernels/pyramid_walk.hpp takes the same steps), or in the cell at `from` when walking on from
  // where a float pass stopped.
  const int top = surface.top_level();
  const double path_cells = (std::fabs(p.dx) + std::fabs(p.dy)) * p.t_max;
  const double bound = std::min((4.0 * path_cells + 64.0) * double(top + 2), 1e13);
  int level = top < 0 ? -1 : 0;
  if (from == 0.0)
    while (level < top && path_cells >= double(1LL << (level + 4))) ++level;
  double t = from;
  for (double pass = 0; pass < bound; ++pass) {
    // Walking on from a float pass: its cell at `from` is solved at once (the pass found it may
    // touch the path).
    if (level >= 0 && interior(cx, w) && interior(cy, h) && !(pass == 0 && from > 0.0)) {
      const long long size = 1LL << level;
      const long long wx = repeat ? wrap_index(cx, w) : cx, wy = repeat ? wrap_index(cy, h) : cy;
      const long long bx = wx >> level, by = wy >> level;
      const long long x_lo = cx - (wx - (bx << level)), y_lo = cy - (wy - (by << level));
      const long long x_hi = repeat ? x_lo + size : std::min(x_lo + size, w - 1);
      const long long y_hi = repeat ? y_lo + size : std::min(y_lo + size, h - 1);
      const double tx = exit_t(p.x0, p.dx, inv_dx, x_lo, x_hi), ty = exit_t(p.y0, p.dy, inv_dy, y_lo, y_hi);
      const double te = std::min(tx, ty);
      const double t_end = std::min(te, p.t_max);
      const double shallowest = surface.shallowest(level, bx, by);
      if (std::max(depth(t), depth(t_end)) < shallowest) {  // the path stays above the block
        if (te >= p.t_max) return result;
        t = te;
        // Step across the exited side(s); the other axis' cell comes from the position.
        const long long nx = p.dx > 0 ? x_hi : x_lo - 1, ny = p.dy > 0 ? y_hi : y_lo - 1;
        const bool up = new_parent(level, tx <= ty, p.dx > 0 ? x_hi : x_lo, ty <= tx, p.dy > 0 ? y_hi : y_lo);
        cx = clamp_cell(tx <= ty ? nx : std::clamp(floor_to_cell(p.x0 + p.dx * t, p.dx), x_lo, x_hi - 1), w);
        cy = clamp_cell(ty <= tx ? ny : std::clamp(floor_to_cell(p.y0 + p.dy * t, p.dy), y_lo, y_hi - 1), h);
        if (up) level = std::min(level + 1, top);
        continue;
      }
      if (level > 0) {
        // A descending path touches nothing in the block before it reaches the block's
        // shallowest depth (depth(t_end) >= shallowest, so that point is inside the block).
        if (p.ddepth > 0.0) {
          const double t_reach = (shallowest - p.depth0) / p.ddepth;
          if (t_reach > t) {
            t = std::min(t_reach, t_end);
            cx = std::clamp(floor_to_cell(p.x0 + p.dx * t, p.dx), x_lo, x_hi - 1);
            cy = std::clamp(floor_to_cell(p.y0 + p.dy * t, p.dy), y_lo, y_hi - 1);
          }
        }
        --level;
        continue;
      }
    }
    const double tx = exit_t(p.x0, p.dx, inv_dx, cell_lo(cx), cell_hi(cx, w));
    const double ty = exit_t(p.y0, p.dy, inv_dy, cell_lo(cy), cell_hi(cy, h));
    const double te = std::max(t, std::min(tx, ty));
    ++result.cells;
    double t_hit;
    if (surface.solve_cell(cx, cy, p, t, std::min(te, p.t_max), t_hit)) {
      result.found = true;
      result.t = t_hit;
      return result;
    }
    if (te >= p.t_max) return result;
    t = te;
    const bool up = new_parent(0, tx <= ty, p.dx > 0 ? cx + 1 : cx, ty <= tx, p.dy > 0 ? cy + 1 : cy);
    if (tx <= ty) cx = clamp_cell(cx + (p.dx > 0 ? 1 : -1), w);
    if (ty <= tx) cy = clamp_cell(cy + (p.dy > 0 ? 1 : -1), h);
    if (up) level = std::min(level + 1, top);
  }
  return result;
}

}  // namespace
}  // namespace heightmarch
