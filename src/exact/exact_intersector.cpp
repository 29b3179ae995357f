#include <algorithm>
#include <cmath>

#include "exact/cell_walk.hpp"
#include "heightmarch/exact.hpp"

namespace heightmarch {

// The level-0 bilinear surface as the walk solves it (cell_walk.hpp), its pyramid the map's.
struct ExactIntersector::Cells {
  const ExactIntersector& x;
  long long width() const { return x.map_->width; }
  long long height() const { return x.map_->height; }
  bool repeat() const { return x.wrap_ == Wrap::repeat; }
  int top_level() const { return x.pyramid_.levels() - 1; }
  double shallowest(int level, long long bx, long long by) const {
    return double(x.pyramid_.at(level, bx, by));
  }
  bool solve_cell(long long ci, long long cj, const HeightfieldPath& p, double t0, double t1,
                  double& t_hit) const {
    return x.cell_first_root(ci, cj, p, t0, t1, t_hit);
  }
};

ExactIntersector::ExactIntersector(const DepthMap& map, Wrap wrap)
    : map_(&map), wrap_(wrap), pyramid_(map, wrap) {}

double ExactIntersector::texel(long long i, long long j) const { return wrapped_texel(*map_, wrap_, i, j); }

double ExactIntersector::depth_at(double x, double y) const {
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const long long i = (long long)x0, j = (long long)y0;
  const double top = texel(i, j) + fx * (texel(i + 1, j) - texel(i, j));
  const double bottom = texel(i, j + 1) + fx * (texel(i + 1, j + 1) - texel(i, j + 1));
  return top + fy * (bottom - top);
}

// Depth minus surface depth along the path inside cell (ci, cj) is a quadratic in t;
// finds its first zero crossing into >= 0 within [t0, t1].
bool ExactIntersector::cell_first_root(long long ci, long long cj, const HeightfieldPath& p, double t0,
                                       double t1, double& t_hit) const {
  const CellQuadratic<double> q =
      cell_quadratic(texel(ci, cj), texel(ci + 1, cj), texel(ci, cj + 1), texel(ci + 1, cj + 1), double(ci),
                     double(cj), p.x0, p.y0, p.dx, p.dy, p.depth0, p.ddepth, t0);
  double s;
  if (!first_root(q, t1 - t0, s)) return false;
  t_hit = t0 + s;
  return true;
}

PathHit ExactIntersector::first_hit(const HeightfieldPath& p, double from) const {
  return walk_cells(Cells{*this}, p, from);
}

PathHit ExactIntersector::intersect(double tx, double ty, double vx, double vy, double vz, double scale,
                                    double from) const {
  PathHit hit = first_hit(ray_path(tx, ty, vx, vy, vz, scale, map_->width, map_->height), from);
  if (!hit.found) {  // only rounding can get here: D <= 1 guarantees a hit by depth 1
    hit.found = true;
    hit.t = 1.0;
  }
  return hit;
}

bool ExactIntersector::visible(double u, double v, double depth, const float light[3], double scale) const {
  // From just above the hit towards the light, until the path reaches the top plane.
  constexpr double kLift = 1e-6;
  const double start = depth - kLift;
  if (start <= 0.0) return true;
  const double w = map_->width, h = map_->height;
  const HeightfieldPath path{u * w - 0.5,
                             v * h - 0.5,
                             scale * light[0] / light[2] * w,
                             scale * light[1] / light[2] * h,
                             start,
                             -1.0,
                             start * (1.0 - 1e-9)};
  return !first_hit(path).found;
}

}  // namespace heightmarch
