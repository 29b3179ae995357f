#include "heightmarch/cone_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>

#include "heightmarch/memory_budget.hpp"

namespace heightmarch {
namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// Floats at or above (below) x: the pyramid's slopes rounded up and depths and distances down
// keep each of its bounds below the exact ones it stands for.
float rounded_up(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
float rounded_down(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

// One sub-patch of a cell, in texel-centre coordinates (texel (i, j) at (i, j)): a bilinear
// patch of its own, with its extent, corner depths, the range of its depth gradient per uv
// (gx over x, gy over y: linear along the other axis, so the edges' differences bound them).
struct SubPatch {
  double x_lo, x_hi, y_lo, y_hi;
  double shallowest;
  double gx_lo, gx_hi, gy_lo, gy_hi;
};

// A bound of |grad D| on the sub-patch.
double gradient_bound(const SubPatch& s) {
  const double gx = std::max(std::fabs(s.gx_lo), std::fabs(s.gx_hi)),
               gy = std::max(std::fabs(s.gy_lo), std::fabs(s.gy_hi));
  return std::sqrt(gx * gx + gy * gy);
}

// The sides of the apex a sub-patch (or block) lies on: 0 when the apex is at or before it along
// the axis (rays from the apex leave towards +), 1 at or after it. Apexes sit on integer
// coordinates and sub-patches never straddle one.
double clipped_slope(const SubPatch& s, int side_x, int side_y) {
  const double ax = side_x == 0 ? std::max({0.0, s.gx_lo, s.gx_hi}) : std::max({0.0, -s.gx_lo, -s.gx_hi});
  const double ay = side_y == 0 ? std::max({0.0, s.gy_lo, s.gy_hi}) : std::max({0.0, -s.gy_lo, -s.gy_hi});
  return std::sqrt(ax * ax + ay * ay);
}

// Per cell and per side of the apex (2 * x side + y side), over its sub-patches that slope away
// from that side: the least depth m and the least m / S (an exit of a ray from the top of the
// apex's axis lies at least that far from it, S the sub-patch's slope bound on that side).
struct CellBound {
  float shallowest[4], rise[4];
  float gx_lo, gx_hi, gy_lo, gy_hi;  // a box holding D's gradient on the cell, per uv
};
using BlockBound = CellBound;  // the same bounds over a block's cells

// A block of the pyramid in one image of the tile (level 0: a cell); level -1: the ring of
// images image_x tiles away (REPEAT).
struct Node {
  int level, bx, by, image_x, image_y;
};

// A texel whose cone is sought: its best bound so far and the cell that gave it.
struct Apex {
  int i, j;
  double depth, best;
  Node argmin;  // level -2: none
};

// A node to open for the texels of a batch in its mask.
struct Entry {
  Node node;
  std::uint32_t mask;
};

// The surface of a depth map under a wrap mode, cut into cells and sub-patches.
class ConeGeometry {
 public:
  ConeGeometry(const DepthMap& map, Wrap wrap)
      : map_(map), repeat_(wrap == Wrap::repeat), width_(map.width), height_(map.height) {}

  // The bound cell (cx, cy) (corners at texel centres (cx, cy) to (cx + 1, cy + 1)), shifted by
  // whole tiles (REPEAT), puts on texel (i, j)'s cone: the least over its sub-patches P with
  // m_P < D_p, S_P > 0 and an exit possible within it (m_P < S_P maxdist(p, P), or unbounded) of
  //   max(dist(p, P), m_P / S_P) / (D_p - m_P), at least 1 / G_P when P touches p,
  // S_P the support of P's gradient box over the directions from p to P. Sub-patches that cannot
  // go below `cutoff` are skipped: the result is exact below it, else kNone.
  double cell_bound(int i, int j, int cx, int cy, int image_x, int image_y, double cutoff = kNone) const {
    const double apex = map_.at(i, j);
    const bool unbounded = is_unbounded(cx, cx + 1, cy, cy + 1);
    // The apex relative to the cell's image, in texel-centre coordinates of the cell's tile.
    const double px = i - double(image_x) * width_, py = j - double(image_y) * height_;
    double best = cutoff;
    for_each_sub_patch(cx, cy, [&](const SubPatch& s) {
      if (!(s.shallowest < apex)) return;
      const double dx = std::max({0.0, s.x_lo - px, px - s.x_hi}) / width_,
                   dy = std::max({0.0, s.y_lo - py, py - s.y_hi}) / height_;
      const double distance2 = dx * dx + dy * dy;
      // The farthest a beating exit may lie (a hair wider: these tests only skip work).
      const double reach = best * (apex - s.shallowest) * (1.0 + 1e-9);
      if (!(distance2 < reach * reach)) return;
      // The slope bound per axis is above the support: a cheaper test first.
      const int side_x = px >= s.x_hi ? 1 : 0, side_y = py >= s.y_hi ? 1 : 0;
      const double clipped = clipped_slope(s, side_x, side_y);
      if (!(s.shallowest < reach * clipped)) return;
      // CLAMP's strips reach infinitely far: their directions are not bounded by corners.
      const double slope = unbounded ? clipped : support_slope(s, px, py);
      if (!(slope > 0.0)) return;
      const double rise = s.shallowest / slope;
      const double far_x = std::max(px - s.x_lo, s.x_hi - px) / width_,
                   far_y = std::max(py - s.y_lo, s.y_hi - py) / height_;
      if (!unbounded && !(rise * rise < far_x * far_x + far_y * far_y)) return;
      const double distance = std::sqrt(distance2);
      double bound = std::max(distance, rise) / (apex - s.shallowest);
      if (distance == 0.0) bound = std::max(bound, 1.0 / gradient_bound(s));  // the depth climbs at most G_P
      best = std::min(best, bound);
    });
    return best < cutoff ? best : kNone;
  }

  float texel(int i, int j) const {
    if (repeat_) return map_.at(((i % width_) + width_) % width_, ((j % height_) + height_) % height_);
    return map_.at(std::clamp(i, 0, width_ - 1), std::clamp(j, 0, height_ - 1));
  }

  // CLAMP's edge cells stand for the strips the clamp extends to infinity.
  bool is_unbounded(int cx0, int cx1, int cy0, int cy1) const {
    return !repeat_ && (cx0 == -1 || cx1 == width_ || cy0 == -1 || cy1 == height_);
  }

  // Calls f on each of the kConeCellSplit^2 sub-patches of cell (cx, cy) (its texel-centre
  // coordinates: corners (cx, cy) to (cx + 1, cy + 1)).
  template <class F>
  void for_each_sub_patch(int cx, int cy, F&& f) const {
    const double t00 = texel(cx, cy), t10 = texel(cx + 1, cy), t01 = texel(cx, cy + 1),
                 t11 = texel(cx + 1, cy + 1);
    constexpr int n = kConeCellSplit;
    double depth[n + 1][n + 1];  // at the sub-patches' corners, [y][x]
    for (int b = 0; b <= n; ++b)
      for (int a = 0; a <= n; ++a) {
        const double fx = double(a) / n, fy = double(b) / n;
        depth[b][a] = t00 + fx * (t10 - t00) + fy * (t01 - t00) + fx * fy * ((t11 - t01) - (t10 - t00));
      }
    const double w = width_ * double(n), h = height_ * double(n);  // per uv, across a sub-patch
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const double s00 = depth[b][a], s10 = depth[b][a + 1], s01 = depth[b + 1][a],
                     s11 = depth[b + 1][a + 1];
        SubPatch s;
        s.x_lo = cx + double(a) / n, s.x_hi = cx + double(a + 1) / n, s.y_lo = cy + double(b) / n,
        s.y_hi = cy + double(b + 1) / n;
        s.shallowest = std::min({s00, s10, s01, s11});
        s.gx_lo = (s10 - s00) * w, s.gx_hi = (s11 - s01) * w;
        s.gy_lo = (s01 - s00) * h, s.gy_hi = (s11 - s10) * h;
        f(s);
      }
  }

  // The largest slope of the sub-patch along any direction from (i, j) into it: the support of
  // its gradient box over the arc of those directions (at a box corner inside the arc, else at
  // an end of the arc).
  double support_slope(const SubPatch& s, double i, double j) const {
    double ax, ay, bx, by;
    arc(s, i, j, ax, ay, bx, by);
    const double a_norm = std::sqrt(ax * ax + ay * ay), b_norm = std::sqrt(bx * bx + by * by);
    ax /= a_norm, ay /= a_norm, bx /= b_norm, by /= b_norm;
    double support = 0.0;
    for (double gx : {s.gx_lo, s.gx_hi})
      for (double gy : {s.gy_lo, s.gy_hi}) {
        const bool inside = ax * gy - ay * gx >= 0.0 && gx * by - gy * bx >= 0.0;
        support = std::max(
            support, inside ? std::sqrt(gx * gx + gy * gy) : std::max(ax * gx + ay * gy, bx * gx + by * gy));
      }
    return support;
  }

  // Whether that support squared exceeds `needed2` (by more than a hair), without roots.
  bool support_exceeds(const SubPatch& s, double i, double j, double needed2) const {
    double ax, ay, bx, by;
    arc(s, i, j, ax, ay, bx, by);
    const double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by;
    const double slack = 1.0 + 1e-9;
    for (double gx : {s.gx_lo, s.gx_hi})
      for (double gy : {s.gy_lo, s.gy_hi}) {
        const bool inside = ax * gy - ay * gx >= 0.0 && gx * by - gy * bx >= 0.0;
        if (inside && (gx * gx + gy * gy) * slack > needed2) return true;
        const double along_a = ax * gx + ay * gy, along_b = bx * gx + by * gy;
        if (along_a > 0.0 && along_a * along_a * slack > needed2 * a2) return true;
        if (along_b > 0.0 && along_b * along_b * slack > needed2 * b2) return true;
      }
    return false;
  }

 private:
  // The ends of the arc of directions (in uv) from (i, j) into the sub-patch, which spans less
  // than a half turn: the directions with every other one counter-clockwise (clockwise) of them.
  void arc(const SubPatch& s, double i, double j, double& ax, double& ay, double& bx, double& by) const {
    double ux[4] = {}, uy[4] = {};
    int n = 0;
    for (double x : {s.x_lo, s.x_hi})
      for (double y : {s.y_lo, s.y_hi}) {
        const double vx = (x - i) / width_, vy = (y - j) / height_;
        if (vx == 0.0 && vy == 0.0) continue;  // the apex itself
        ux[n] = vx, uy[n] = vy, ++n;
      }
    int first = 0, last = 0;
    for (int k = 1; k < n; ++k) {
      if (ux[first] * uy[k] - uy[first] * ux[k] < 0.0) first = k;
      if (ux[last] * uy[k] - uy[last] * ux[k] > 0.0) last = k;
    }
    ax = ux[first], ay = uy[first], bx = ux[last], by = uy[last];
  }

  const DepthMap& map_;
  bool repeat_;
  int width_, height_;
};

// The pyramid of cell bounds and the search for each texel's cone.
class ConeBuilder {
 public:
  ConeBuilder(const DepthMap& map, Wrap wrap)
      : geometry_(map, wrap),
        repeat_(wrap == Wrap::repeat),
        first_(repeat_ ? 0 : -1),
        cells_x_(repeat_ ? map.width : map.width + 1),
        cells_y_(repeat_ ? map.height : map.height + 1),
        width_(map.width),
        height_(map.height) {
    build_cells();
    build_levels();
  }

  // The cones of a batch of texels, found with one depth-first walk of the pyramid: a block is
  // opened for the texels for which it may hold a cell bounding their cone below their best so
  // far, starting from the cell that bounded a neighbour's (the texel's `argmin` on entry).
  void ratios(Apex* apexes, int count, std::vector<Entry>& stack) const {
    std::uint32_t all = 0;
    for (int k = 0; k < count; ++k) {
      Apex& a = apexes[k];
      a.best = kMaxConeRatio;
      if (!(shallowest_ < a.depth)) continue;  // no cell above the apex slopes away from anything
      all |= 1u << k;
      if (a.argmin.level != 0) continue;
      const double bound = cell_bound(a, a.argmin);
      if (bound < a.best)
        a.best = bound;
      else
        a.argmin.level = -2;
    }
    if (!all) return;
    stack.clear();
    const int top = int(levels_.size());  // levels_ holds levels 1 and up
    if (repeat_) stack.push_back({{-1, 0, 0, 1, 0}, all});
    stack.push_back({{top, 0, 0, 0, 0}, all});
    // The batch's centre, to open the nearest children first.
    const double centre_x = 0.5 * (apexes[0].i + apexes[count - 1].i),
                 centre_y = 0.5 * (apexes[0].j + apexes[count - 1].j);
    while (!stack.empty()) {
      const Entry entry = stack.back();
      stack.pop_back();
      const Node& node = entry.node;
      std::uint32_t mask = 0;
      const BlockView block = node.level < 0 ? BlockView{} : view(node);
      for (std::uint32_t m = entry.mask; m; m &= m - 1) {
        const Apex& a = apexes[std::countr_zero(m)];
        // REPEAT: the images k tiles away are at least k - 1 uv from the apex, in tile 0.
        const bool open =
            node.level < 0 ? node.image_x - 1 < a.best * (a.depth - shallowest_) : may_beat(block, a);
        if (open) mask |= m & (~m + 1);
      }
      if (!mask) continue;
      if (node.level < 0) {  // the images of a ring, and the next ring
        const int k = node.image_x;
        stack.push_back({{-1, 0, 0, k + 1, 0}, mask});
        for (int y = -k; y <= k; ++y)
          for (int x = -k; x <= k; x += (y == -k || y == k) ? 1 : 2 * k)
            stack.push_back({{top, 0, 0, x, y}, mask});
      } else if (node.level == 0) {
        for (std::uint32_t m = mask; m; m &= m - 1) {
          Apex& a = apexes[std::countr_zero(m)];
          const double bound = cell_bound(a, node);
          if (bound < a.best) {
            a.best = bound;
            a.argmin = node;
          }
        }
      } else {
        const int level = node.level - 1, size = 1 << level;
        const int blocks_x = level_blocks_x_[std::size_t(level)],
                  blocks_y = level_blocks_y_[std::size_t(level)];
        Entry children[4];
        double distance[4];
        int n = 0;
        for (int cy = 2 * node.by; cy < std::min(2 * node.by + 2, blocks_y); ++cy)
          for (int cx = 2 * node.bx; cx < std::min(2 * node.bx + 2, blocks_x); ++cx) {
            const double x = first_ + (cx + 0.5) * size + double(node.image_x) * width_ - centre_x;
            const double y = first_ + (cy + 0.5) * size + double(node.image_y) * height_ - centre_y;
            int at = n++;
            for (; at > 0 && distance[at - 1] < x * x + y * y; --at)
              children[at] = children[at - 1], distance[at] = distance[at - 1];
            children[at] = {{level, cx, cy, node.image_x, node.image_y}, mask};
            distance[at] = x * x + y * y;
          }
        stack.insert(stack.end(), children, children + n);  // farthest first: the nearest is opened next
      }
    }
  }

 private:
  bool is_unbounded(int cx0, int cx1, int cy0, int cy1) const {
    return geometry_.is_unbounded(cx0, cx1, cy0, cy1);
  }

  void build_cells() {
    cells_.resize(std::size_t(cells_x_) * std::size_t(cells_y_));
    tbb::parallel_for(0, cells_y_, [&](int y) {
      for (int x = 0; x < cells_x_; ++x) {
        CellBound& c = cells_[std::size_t(y) * std::size_t(cells_x_) + std::size_t(x)];
        std::fill(std::begin(c.shallowest), std::end(c.shallowest), 2.0f);
        std::fill(std::begin(c.rise), std::end(c.rise), std::numeric_limits<float>::infinity());
        double gx_lo = kNone, gx_hi = -kNone, gy_lo = kNone, gy_hi = -kNone;
        geometry_.for_each_sub_patch(first_ + x, first_ + y, [&](const SubPatch& s) {
          gx_lo = std::min({gx_lo, s.gx_lo, s.gx_hi}), gx_hi = std::max({gx_hi, s.gx_lo, s.gx_hi});
          gy_lo = std::min({gy_lo, s.gy_lo, s.gy_hi}), gy_hi = std::max({gy_hi, s.gy_lo, s.gy_hi});
          for (int q = 0; q < 4; ++q) {
            // The side's slope bound: above the support over any arc on that side.
            const double slope = clipped_slope(s, q / 2, q % 2);
            if (!(slope > 0.0)) continue;
            c.shallowest[q] = std::min(c.shallowest[q], rounded_down(s.shallowest));
            c.rise[q] = std::min(c.rise[q], rounded_down(s.shallowest / slope));
          }
        });
        c.gx_lo = rounded_down(gx_lo), c.gx_hi = rounded_up(gx_hi), c.gy_lo = rounded_down(gy_lo),
        c.gy_hi = rounded_up(gy_hi);
      }
    });
  }

  // Level 1 blocks 2 x 2 cells, each level halves rounding up, to a single block.
  void build_levels() {
    int bx = cells_x_, by = cells_y_;
    level_blocks_x_.push_back(bx);
    level_blocks_y_.push_back(by);
    while (bx > 1 || by > 1) {
      const std::vector<BlockBound>& fine = levels_.empty() ? cells_ : levels_.back();
      const int fine_x = bx, fine_y = by;
      bx = (bx + 1) / 2;
      by = (by + 1) / 2;
      std::vector<BlockBound> blocks(std::size_t(bx) * std::size_t(by));
      tbb::parallel_for(0, by, [&](int y) {
        for (int x = 0; x < bx; ++x) {
          BlockBound& b = blocks[std::size_t(y) * std::size_t(bx) + std::size_t(x)];
          std::fill(std::begin(b.shallowest), std::end(b.shallowest), 2.0f);
          std::fill(std::begin(b.rise), std::end(b.rise), std::numeric_limits<float>::infinity());
          b.gx_lo = b.gy_lo = std::numeric_limits<float>::infinity();
          b.gx_hi = b.gy_hi = -std::numeric_limits<float>::infinity();
          for (int fy = 2 * y; fy < std::min(2 * y + 2, fine_y); ++fy)
            for (int fx = 2 * x; fx < std::min(2 * x + 2, fine_x); ++fx) {
              const BlockBound& f = fine[std::size_t(fy) * std::size_t(fine_x) + std::size_t(fx)];
              for (int q = 0; q < 4; ++q) {
                b.shallowest[q] = std::min(b.shallowest[q], f.shallowest[q]);
                b.rise[q] = std::min(b.rise[q], f.rise[q]);
              }
              b.gx_lo = std::min(b.gx_lo, f.gx_lo), b.gx_hi = std::max(b.gx_hi, f.gx_hi);
              b.gy_lo = std::min(b.gy_lo, f.gy_lo), b.gy_hi = std::max(b.gy_hi, f.gy_hi);
            }
        }
      });
      levels_.push_back(std::move(blocks));
      level_blocks_x_.push_back(bx);
      level_blocks_y_.push_back(by);
    }
    const BlockBound& all = levels_.empty() ? cells_.front() : levels_.back().front();
    shallowest_ = *std::min_element(std::begin(all.shallowest), std::end(all.shallowest));
  }

  // The exact bound of a cell (`first_`-based grid indices in the node) on an apex's cone, where
  // below its best so far (else kNone).
  double cell_bound(const Apex& a, const Node& cell) const {
    return geometry_.cell_bound(a.i, a.j, first_ + cell.bx, first_ + cell.by, cell.image_x, cell.image_y,
                                a.best);
  }

  // A block (or cell) in one image of the tile, as the tests of every texel of a batch see it.
  struct BlockView {
    const BlockBound* bound;
    double x_lo, x_hi, y_lo, y_hi;  // its extent in texel-centre coordinates (cell k spans [k, k + 1])
    bool unbounded;
  };

  BlockView view(const Node& node) const {
    const int size = 1 << node.level;
    const int cx0 = node.bx * size, cx1 = std::min(cx0 + size, cells_x_);
    const int cy0 = node.by * size, cy1 = std::min(cy0 + size, cells_y_);
    BlockView v;
    v.bound = node.level == 0
                  ? &cells_[std::size_t(cy0) * std::size_t(cells_x_) + std::size_t(cx0)]
                  : &levels_[std::size_t(node.level - 1)]
                            [std::size_t(node.by) * std::size_t(level_blocks_x_[std::size_t(node.level)]) +
                             std::size_t(node.bx)];
    v.x_lo = first_ + cx0 + double(node.image_x) * width_,
    v.x_hi = first_ + cx1 + double(node.image_x) * width_;
    v.y_lo = first_ + cy0 + double(node.image_y) * height_,
    v.y_hi = first_ + cy1 + double(node.image_y) * height_;
    v.unbounded = is_unbounded(first_ + cx0, first_ + cx1, first_ + cy0, first_ + cy1);
    return v;
  }

  // Whether a block (or cell) may hold a cell bounding the apex's cone below its best: the
  // pyramid's lower bound max(dist, m / S) / (D_p - m) against the best, compared squared; S per axis, then
  // along the directions from the apex into the block (the support of its gradient box over their arc).
  bool may_beat(const BlockView& v, const Apex& a) const {
    const BlockBound& b = *v.bound;
    // The sides of the apex the block's cells lie on.
    const int side_x_first = a.i >= v.x_hi ? 1 : 0, side_x_last = a.i <= v.x_lo ? 0 : 1;
    const int side_y_first = a.j >= v.y_hi ? 1 : 0, side_y_last = a.j <= v.y_lo ? 0 : 1;
    double shallowest = 2.0, rise = kNone;
    for (int sx = side_x_first; sx <= side_x_last; ++sx)
      for (int sy = side_y_first; sy <= side_y_last; ++sy) {
        shallowest = std::min(shallowest, double(b.shallowest[2 * sx + sy]));
        rise = std::min(rise, double(b.rise[2 * sx + sy]));
      }
    if (!(shallowest < a.depth)) return false;
    const double far_x = std::max(a.i - v.x_lo, v.x_hi - a.i) * inv_width_,
                 far_y = std::max(a.j - v.y_lo, v.y_hi - a.j) * inv_height_;
    const double far2 = far_x * far_x + far_y * far_y;
    if (!v.unbounded && !(rise * rise < far2 * (1.0 + 1e-9))) return false;
    const double dx = std::max({0.0, v.x_lo - a.i, a.i - v.x_hi}) * inv_width_,
                 dy = std::max({0.0, v.y_lo - a.j, a.j - v.y_hi}) * inv_height_;
    const double distance2 = dx * dx + dy * dy;
    const double reach = a.best * (a.depth - shallowest);  // the farthest a beating exit may lie
    // A hair of slack: rounding in the squares never prunes a cell the division would keep.
    const double reach2 = reach * reach * (1.0 + 1e-9);
    if (!(std::max(distance2, rise * rise) < reach2)) return false;
    // The arc spans less than a half turn when the apex lies beside the block or at a corner.
    const bool beside = a.i < v.x_lo || a.i > v.x_hi || a.j < v.y_lo || a.j > v.y_hi;
    const bool corner = (a.i == v.x_lo || a.i == v.x_hi) && (a.j == v.y_lo || a.j == v.y_hi);
    if ((beside || corner) && !v.unbounded) {
      // m / S below both the reach and the farthest point: S^2 above m^2 / min(reach^2, far^2).
      const SubPatch box{v.x_lo, v.x_hi, v.y_lo, v.y_hi, shallowest, b.gx_lo, b.gx_hi, b.gy_lo, b.gy_hi};
      if (!geometry_.support_exceeds(box, a.i, a.j,
                                     shallowest * shallowest / (std::min(reach2, far2) * (1.0 + 1e-9))))
        return false;
    }
    return true;
  }

  ConeGeometry geometry_;
  bool repeat_;
  int first_;  // texel-centre coordinate of cell 0's left (top) edge: CLAMP's strips come first
  int cells_x_, cells_y_;
  int width_, height_;
  double inv_width_ = 1.0 / width_, inv_height_ = 1.0 / height_;
  std::vector<CellBound> cells_;
  std::vector<std::vector<BlockBound>> levels_;  // levels_[L - 1]: blocks of 2^L x 2^L cells
  std::vector<int> level_blocks_x_, level_blocks_y_;
  float shallowest_ = 2.0f;  // the least m of any sub-patch that slopes away from any side
};

}  // namespace

ConeMap build_cone_map(const DepthMap& map, Wrap wrap) {
  const auto start = std::chrono::steady_clock::now();
  check_memory_budget(64.0 * double(map.width + 1) * double(map.height + 1), "the cone map");
  ConeMap cone;
  cone.width = map.width;
  cone.height = map.height;
  cone.wrap = wrap;
  cone.depth = map.texels;
  cone.ratio.resize(map.texels.size());
  const ConeBuilder builder(map, wrap);
  // Batches of kBatchSide x kBatchSide texels, each starting from the cells that bounded the
  // batch before it in the row.
  constexpr int kBatchSide = 4;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, (map.height + kBatchSide - 1) / kBatchSide),
      [&](const tbb::blocked_range<int>& rows) {
        std::vector<Entry> stack;
        Apex apexes[kBatchSide * kBatchSide];
        for (int row = rows.begin(); row != rows.end(); ++row) {
          for (Apex& a : apexes) a.argmin.level = -2;
          const int j0 = row * kBatchSide, j1 = std::min(j0 + kBatchSide, map.height);
          for (int i0 = 0; i0 < map.width; i0 += kBatchSide) {
            const int i1 = std::min(i0 + kBatchSide, map.width);
            int count = 0;
            for (int j = j0; j < j1; ++j)
              for (int i = i0; i < i1; ++i) {
                Apex& a = apexes[count++];
                a.i = i, a.j = j, a.depth = map.at(i, j);
              }
            builder.ratios(apexes, count, stack);
            for (int k = 0; k < count; ++k)
              cone.ratio[std::size_t(apexes[k].j) * std::size_t(map.width) + std::size_t(apexes[k].i)] =
                  rounded_down(apexes[k].best);
          }
        }
      });
  cone.texture = SamplerTexture(DepthMap{map.width, map.height, cone.ratio}, wrap);
  cone.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cone;
}

double cone_cell_bound(const DepthMap& map, Wrap wrap, int i, int j, int cell_x, int cell_y) {
  const int tile_x = wrap == Wrap::repeat ? int(std::floor(double(cell_x) / map.width)) : 0;
  const int tile_y = wrap == Wrap::repeat ? int(std::floor(double(cell_y) / map.height)) : 0;
  return ConeGeometry(map, wrap).cell_bound(i, j, cell_x - tile_x * map.width, cell_y - tile_y * map.height,
                                            tile_x, tile_y);
}

std::shared_ptr<const ConeMap> cached_cone_map(const DepthMap& map, Wrap wrap) {
  static std::mutex mutex;
  static std::vector<std::shared_ptr<const ConeMap>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  for (const auto& cone : cache)
    if (cone->wrap == wrap && cone->width == map.width && cone->height == map.height &&
        cone->depth == map.texels)
      return cone;
  cache.push_back(std::make_shared<const ConeMap>(build_cone_map(map, wrap)));
  return cache.back();
}

GlImage ConeMap::gl_image() const {
  GlImage image;
  image.width = width;
  image.height = height;
  image.channels = 2;
  image.linear = true;
  image.run_wrap = true;
  image.texels.resize(2 * depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    image.texels[2 * i] = depth[i];
    image.texels[2 * i + 1] = ratio[i];
  }
  return image;
}

}  // namespace heightmarch
