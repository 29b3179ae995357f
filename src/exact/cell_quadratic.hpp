#pragma once
// A texel cell's bilinear patch along a path, as a quadratic in double, and its first crossing:
// shared by the double walk (exact_intersector.cpp, T = double) and the exact reference's
// refinement of the cell its float pass stopped in (src/exact/exact_bound.hpp, T = vdouble<D>, D
// lanes at once), which so solves it as the walk does, bit for bit: the packet ops round and
// pick as the scalar ones (src/simd/packet.hpp), and -ffp-contract=off keeps every
// product apart. Unqualified calls take std:: for double and the packet's overloads by ADL.
// Internal linkage: each ISA's translation unit (compiled with its own flags) keeps its own copy.
#include <algorithm>
#include <cmath>

namespace heightmarch {
namespace {

// m ? a : c, as the packets' select.
inline double select(bool m, double a, double c) { return m ? a : c; }

// A number type's mask: bool for double, vboold<D> for vdouble<D>.
template <class T>
using MaskOf = decltype(T() < T());

// depth(t) - D(x(t), y(t)) in cell (ci, cj) with texels t00, t10, t01, t11, as
// c0 + c1 s + c2 s^2 with s = t - t0 (parametrised from t0 for precision).
template <class T>
struct CellQuadratic {
  T c0, c1, c2;
};

template <class T>
CellQuadratic<T> cell_quadratic(T t00, T t10, T t01, T t11, T ci, T cj, T x0, T y0, T dx, T dy, T depth0,
                                T ddepth, T t0) {
  const T e = t10 - t00, f = t01 - t00, g = t11 - t10 - t01 + t00;
  const T fx = (x0 - ci) + dx * t0;  // blend weights at t0
  const T fy = (y0 - cj) + dy * t0;
  const T surface0 = t00 + e * fx + f * fy + g * fx * fy;
  return {(depth0 + ddepth * t0) - surface0, ddepth - (e * dx + f * dy + g * (fx * dy + fy * dx)),
          -g * dx * dy};
}

// Where a cell's quadratic first crosses into >= 0 within [0, span]: `crosses` with the crossing
// at s (0 if it starts there); `hidden` when no root shows but it ends at or above 0 (rounding
// hid the root: the caller bisects); neither: no crossing.
template <class T>
struct CellCrossing {
  MaskOf<T> crosses, hidden;
  T s;
};

template <class T>
CellCrossing<T> first_crossing(const CellQuadratic<T>& q, T span) {
  using std::abs, std::copysign, std::max, std::sqrt;
  using M = MaskOf<T>;
  const T zero(0.0);
  const T c0 = q.c0, c1 = q.c1, c2 = q.c2;
  // Roots of c2 s^2 + c1 s + c0, smallest first; c0 < 0 so the first root in range is the crossing.
  const M linear = abs(c2) * span <= T(1e-14) * (abs(c1) + abs(c0) / max(span, T(1e-300)));
  const T r_linear = -c0 / c1;
  const T disc = c1 * c1 - T(4.0) * c2 * c0;
  const T qq = T(-0.5) * (c1 + copysign(sqrt(max(disc, zero)), c1));
  const T r1 = qq / c2, r2 = c0 / qq;
  const M two = qq != zero;
  const M swap = two & (r2 < r1);
  const T lo = select(swap, r2, r1), hi = select(swap, r1, r2);
  const M linear_in = linear & (c1 > zero) & (r_linear >= zero) & (r_linear <= span);
  const M quadratic = (!linear) & (disc >= zero);
  const M lo_in = quadratic & (lo >= zero) & (lo <= span);
  const M hi_in = quadratic & two & (hi >= zero) & (hi <= span);
  const M starts_above = c0 >= zero;
  const M crosses = starts_above | linear_in | lo_in | hi_in;
  const M hidden = (!crosses) & (c0 + span * (c1 + span * c2) >= zero);  // ends at or above 0
  return {crosses, hidden, select(starts_above, zero, select(linear, r_linear, select(lo_in, lo, hi)))};
}

}  // namespace
}  // namespace heightmarch
