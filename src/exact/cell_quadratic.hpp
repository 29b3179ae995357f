#pragma once
// A texel cell's bilinear patch along a path, as a quadratic in double, and its first crossing:
// shared by the double walk (exact_intersector.cpp) and the exact reference's refinement of the
// cell its float pass stopped in (src/kernels/maxmip.hpp), which so solves it as the walk does.
// Internal linkage: each ISA's translation unit (compiled with its own flags) keeps its own copy.
#include <algorithm>
#include <cmath>

namespace heightmarch {
namespace {

// depth(t) - D(x(t), y(t)) in cell (ci, cj) with texels t00, t10, t01, t11, as
// c0 + c1 s + c2 s^2 with s = t - t0 (parametrised from t0 for precision).
struct CellQuadratic {
  double c0, c1, c2;
};

inline CellQuadratic cell_quadratic(double t00, double t10, double t01, double t11, double ci, double cj,
                                    double x0, double y0, double dx, double dy, double depth0, double ddepth,
                                    double t0) {
  const double e = t10 - t00, f = t01 - t00, g = t11 - t10 - t01 + t00;
  const double fx = (x0 - ci) + dx * t0;  // blend weights at t0
  const double fy = (y0 - cj) + dy * t0;
  const double surface0 = t00 + e * fx + f * fy + g * fx * fy;
  return {(depth0 + ddepth * t0) - surface0, ddepth - (e * dx + f * dy + g * (fx * dy + fy * dx)), -g * dx * dy};
}

enum CellCrossing { kNoCrossing, kCrossing, kHiddenCrossing };

// The first s in [0, span] where the quadratic crosses into >= 0 (0 if it starts there):
// kCrossing with s; kHiddenCrossing when no root shows but it ends at or above 0 (rounding hid
// the root: the caller bisects); else kNoCrossing.
inline CellCrossing first_crossing(const CellQuadratic& q, double span, double& s) {
  const double c0 = q.c0, c1 = q.c1, c2 = q.c2;
  // Roots of c2 s^2 + c1 s + c0, smallest first; c0 < 0 so the first root in range is the crossing.
  const bool linear = std::fabs(c2) * span <= 1e-14 * (std::fabs(c1) + std::fabs(c0) / std::max(span, 1e-300));
  const double r_linear = -c0 / c1;
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  const double qq = -0.5 * (c1 + std::copysign(std::sqrt(std::max(disc, 0.0)), c1));
  const double r1 = qq / c2, r2 = c0 / qq;
  const bool two = qq != 0.0;
  const double lo = two && r2 < r1 ? r2 : r1, hi = two && r2 < r1 ? r1 : r2;
  const bool linear_in = linear & (c1 > 0.0) & (r_linear >= 0.0) & (r_linear <= span);
  const bool quadratic = !linear & (disc >= 0.0);
  const bool lo_in = quadratic & (lo >= 0.0) & (lo <= span);
  const bool hi_in = quadratic & two & (hi >= 0.0) & (hi <= span);
  s = c0 >= 0.0 ? 0.0 : linear ? r_linear : lo_in ? lo : hi;
  const bool crosses = (c0 >= 0.0) | linear_in | lo_in | hi_in;
  const bool ends_above = c0 + span * (c1 + span * c2) >= 0.0;
  return crosses ? kCrossing : ends_above ? kHiddenCrossing : kNoCrossing;
}

}  // namespace
}  // namespace heightmarch
