#include "heightmarch/cone_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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
  double gradient;  // bound of |grad D| on it
};

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
  float gradient;  // bound of |grad D| on the cell
};
using BlockBound = CellBound;  // the same bounds over a block's cells (gradient unused)

// A block of the pyramid in one image of the tile (level 0: a cell, `exact` once its
// sub-patches were evaluated); level -1: the ring of images image_x tiles away (REPEAT).
struct Node {
  double lower_bound;
  int level, bx, by, image_x, image_y;
  bool exact;
  bool operator<(const Node& o) const { return lower_bound > o.lower_bound; }  // a min-heap
};

// The surface of a depth map under a wrap mode, cut into cells and sub-patches.
class ConeGeometry {
 public:
  ConeGeometry(const DepthMap& map, Wrap wrap)
      : map_(map), repeat_(wrap == Wrap::repeat), width_(map.width), height_(map.height) {}

  // The bound cell (cx, cy) of `first_`-based cell indices, shifted by whole tiles (REPEAT),
  // puts on texel (i, j)'s cone: the least over its sub-patches P with m_P < D_p, S_P > 0 and
  // an exit possible within it (m_P < S_P maxdist(p, P), or unbounded) of
  //   max(dist(p, P), m_P / S_P) / (D_p - m_P), at least 1 / G_P when P touches p,
  // S_P the support of P's gradient box over the directions from p to P. Sub-patches that cannot
  // go below `cutoff` are skipped: the result is exact below it, else kNone.
  double cell_bound(int i, int j, int cx, int cy, int image_x, int image_y, double cutoff = kNone) const {
    const double apex = map_.at(i, j);
    const bool unbounded = is_unbounded(cx, cx + 1, cy, cy + 1);
    double best = cutoff;
    for_each_sub_patch(cx, cy, [&](SubPatch s) {
      if (!(s.shallowest < apex)) return;
      s.x_lo += double(image_x) * width_, s.x_hi += double(image_x) * width_;
      s.y_lo += double(image_y) * height_, s.y_hi += double(image_y) * height_;
      const double dx = std::max({0.0, s.x_lo - i, i - s.x_hi}) / width_, dy = std::max({0.0, s.y_lo - j, j - s.y_hi}) / height_;
      const double distance = std::sqrt(dx * dx + dy * dy);
      const double height = apex - s.shallowest;
      if (!(distance < best * height)) return;
      // The slope bound per axis is above the support: a cheaper test first.
      const int side_x = i >= s.x_hi ? 1 : 0, side_y = j >= s.y_hi ? 1 : 0;
      const double clipped = clipped_slope(s, side_x, side_y);
      if (!(s.shallowest < best * height * clipped)) return;
      // CLAMP's strips reach infinitely far: their directions are not bounded by corners.
      const double slope = unbounded ? clipped : support_slope(s, i, j);
      if (!(slope > 0.0)) return;
      const double rise = s.shallowest / slope;
      const double far_x = std::max(i - s.x_lo, s.x_hi - i) / width_, far_y = std::max(j - s.y_lo, s.y_hi - j) / height_;
      if (!unbounded && !(rise * rise < far_x * far_x + far_y * far_y)) return;
      double bound = std::max(distance, rise) / height;
      if (distance == 0.0) bound = std::max(bound, 1.0 / s.gradient);  // the depth climbs at most G_P
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
    const double t00 = texel(cx, cy), t10 = texel(cx + 1, cy), t01 = texel(cx, cy + 1), t11 = texel(cx + 1, cy + 1);
    const auto depth = [&](double fx, double fy) {
      return t00 + fx * (t10 - t00) + fy * (t01 - t00) + fx * fy * ((t11 - t01) - (t10 - t00));
    };
    constexpr int n = kConeCellSplit;
    const double w = width_ * double(n), h = height_ * double(n);  // per uv, across a sub-patch
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const double fx0 = double(a) / n, fx1 = double(a + 1) / n, fy0 = double(b) / n, fy1 = double(b + 1) / n;
        const double s00 = depth(fx0, fy0), s10 = depth(fx1, fy0), s01 = depth(fx0, fy1), s11 = depth(fx1, fy1);
        SubPatch s;
        s.x_lo = cx + fx0, s.x_hi = cx + fx1, s.y_lo = cy + fy0, s.y_hi = cy + fy1;
        s.shallowest = std::min({s00, s10, s01, s11});
        s.gx_lo = (s10 - s00) * w, s.gx_hi = (s11 - s01) * w;
        s.gy_lo = (s01 - s00) * h, s.gy_hi = (s11 - s10) * h;
        const double gx = std::max(std::fabs(s.gx_lo), std::fabs(s.gx_hi)), gy = std::max(std::fabs(s.gy_lo), std::fabs(s.gy_hi));
        s.gradient = std::sqrt(gx * gx + gy * gy);
        f(s);
      }
  }

  const DepthMap& map() const { return map_; }
  bool repeat() const { return repeat_; }

 private:
  // The largest slope of the sub-patch along any direction from (i, j) into it: the support of
  // its gradient box over the arc of those directions (at a box corner inside the arc, else at
  // an end of the arc).
  double support_slope(const SubPatch& s, int i, int j) const {
    double ux[4], uy[4];
    int n = 0;
    for (double x : {s.x_lo, s.x_hi})
      for (double y : {s.y_lo, s.y_hi}) {
        const double vx = (x - i) / width_, vy = (y - j) / height_;
        if (vx == 0.0 && vy == 0.0) continue;  // the apex itself
        ux[n] = vx, uy[n] = vy, ++n;
      }
    // The arc's ends (it spans less than a half turn): the directions with every other one
    // counter-clockwise (clockwise) of them.
    int first = 0, last = 0;
    for (int k = 1; k < n; ++k) {
      if (ux[first] * uy[k] - uy[first] * ux[k] < 0.0) first = k;
      if (ux[last] * uy[k] - uy[last] * ux[k] > 0.0) last = k;
    }
    const double first_norm = std::sqrt(ux[first] * ux[first] + uy[first] * uy[first]);
    const double last_norm = std::sqrt(ux[last] * ux[last] + uy[last] * uy[last]);
    const double ax = ux[first] / first_norm, ay = uy[first] / first_norm;
    const double bx = ux[last] / last_norm, by = uy[last] / last_norm;
    double support = 0.0;
    for (double gx : {s.gx_lo, s.gx_hi})
      for (double gy : {s.gy_lo, s.gy_hi}) {
        const bool inside = ax * gy - ay * gx >= 0.0 && gx * by - gy * bx >= 0.0;
        support = std::max(support, inside ? std::sqrt(gx * gx + gy * gy) : std::max(ax * gx + ay * gy, bx * gx + by * gy));
      }
    return support;
  }

  const DepthMap& map_;
  bool repeat_;
  int width_, height_;
};

// The pyramid of cell bounds and the search for each texel's cone.
class ConeBuilder {
 public:
  ConeBuilder(const DepthMap& map, Wrap wrap)
      : geometry_(map, wrap), map_(map), repeat_(wrap == Wrap::repeat), first_(repeat_ ? 0 : -1),
        cells_x_(repeat_ ? map.width : map.width + 1), cells_y_(repeat_ ? map.height : map.height + 1),
        width_(map.width), height_(map.height) {
    build_cells();
    build_levels();
  }

  // c(p) of texel (i, j): the best-first search of the pyramid, pruning every block whose
  // lower bound is no better than the best cone found. `hint`: a cell that bounded a
  // neighbouring texel's cone (level -2 if none), tried first; on return the cell bounding this
  // one's.
  double ratio(int i, int j, std::vector<Node>& heap, Node& hint) const {
    const double apex = map_.at(i, j);
    double best = kMaxConeRatio;
    if (!(shallowest_ < apex)) return best;  // no cell above the apex slopes away from anything
    if (hint.level == 0) {
      const double bound = geometry_.cell_bound(i, j, first_ + hint.bx, first_ + hint.by, hint.image_x, hint.image_y, best);
      if (bound < best) best = bound;
      else hint.level = -2;
    }
    heap.clear();
    const int top = int(levels_.size());  // levels_ holds levels 1 and up
    push(heap, {0, top, 0, 0, 0, 0, false}, i, j, apex, best);
    if (repeat_) push_ring(heap, 1, apex, best);
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end());
      Node node = heap.back();
      heap.pop_back();
      if (node.lower_bound >= best) break;
      if (node.level < 0) {  // the images of a ring, and the next ring
        const int k = node.image_x;
        for (int y = -k; y <= k; ++y)
          for (int x = -k; x <= k; x += (y == -k || y == k) ? 1 : 2 * k) push(heap, {0, top, 0, 0, x, y, false}, i, j, apex, best);
        push_ring(heap, k + 1, apex, best);
      } else if (node.level == 0 && node.exact) {
        best = node.lower_bound;
        hint = node;
      } else if (node.level == 0) {  // back in line with its exact bound
        node.lower_bound = geometry_.cell_bound(i, j, first_ + node.bx, first_ + node.by, node.image_x, node.image_y, best);
        node.exact = true;
        if (node.lower_bound < best) {
          heap.push_back(node);
          std::push_heap(heap.begin(), heap.end());
        }
      } else {
        const int level = node.level - 1;
        const int blocks_x = level_blocks_x_[std::size_t(level)], blocks_y = level_blocks_y_[std::size_t(level)];
        for (int cy = 2 * node.by; cy < std::min(2 * node.by + 2, blocks_y); ++cy)
          for (int cx = 2 * node.bx; cx < std::min(2 * node.bx + 2, blocks_x); ++cx)
            push(heap, {0, level, cx, cy, node.image_x, node.image_y, false}, i, j, apex, best);
      }
    }
    return best;
  }

 private:
  bool is_unbounded(int cx0, int cx1, int cy0, int cy1) const { return geometry_.is_unbounded(cx0, cx1, cy0, cy1); }

  void build_cells() {
    cells_.resize(std::size_t(cells_x_) * std::size_t(cells_y_));
    tbb::parallel_for(0, cells_y_, [&](int y) {
      for (int x = 0; x < cells_x_; ++x) {
        CellBound& c = cells_[std::size_t(y) * std::size_t(cells_x_) + std::size_t(x)];
        std::fill(std::begin(c.shallowest), std::end(c.shallowest), 2.0f);
        std::fill(std::begin(c.rise), std::end(c.rise), std::numeric_limits<float>::infinity());
        double gradient = 0.0;
        geometry_.for_each_sub_patch(first_ + x, first_ + y, [&](const SubPatch& s) {
          gradient = std::max(gradient, s.gradient);
          for (int q = 0; q < 4; ++q) {
            // The side's slope bound: above the support over any arc on that side.
            const double slope = clipped_slope(s, q / 2, q % 2);
            if (!(slope > 0.0)) continue;
            c.shallowest[q] = std::min(c.shallowest[q], rounded_down(s.shallowest));
            c.rise[q] = std::min(c.rise[q], rounded_down(s.shallowest / slope));
          }
        });
        c.gradient = rounded_up(gradient);
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
          for (int fy = 2 * y; fy < std::min(2 * y + 2, fine_y); ++fy)
            for (int fx = 2 * x; fx < std::min(2 * x + 2, fine_x); ++fx)
              for (int q = 0; q < 4; ++q) {
                const BlockBound& f = fine[std::size_t(fy) * std::size_t(fine_x) + std::size_t(fx)];
                b.shallowest[q] = std::min(b.shallowest[q], f.shallowest[q]);
                b.rise[q] = std::min(b.rise[q], f.rise[q]);
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

  // A lower bound of a block's (or cell's) contribution to texel (i, j)'s cone, from the
  // pyramid; kNone when none of its cells can bound it.
  double lower_bound(const Node& node, int i, int j, double apex) const {
    const int size = 1 << node.level;
    const int cx0 = node.bx * size, cx1 = std::min(cx0 + size, cells_x_);
    const int cy0 = node.by * size, cy1 = std::min(cy0 + size, cells_y_);
    // The block's extent in texel-centre coordinates (cell k spans [k, k + 1]).
    const double x_lo = first_ + cx0 + double(node.image_x) * width_, x_hi = first_ + cx1 + double(node.image_x) * width_;
    const double y_lo = first_ + cy0 + double(node.image_y) * height_, y_hi = first_ + cy1 + double(node.image_y) * height_;
    const BlockBound& b = node.level == 0 ? cells_[std::size_t(cy0) * std::size_t(cells_x_) + std::size_t(cx0)]
                                          : levels_[std::size_t(node.level - 1)][std::size_t(node.by) * std::size_t(level_blocks_x_[std::size_t(node.level)]) +
                                                                                 std::size_t(node.bx)];
    // The sides of the apex the block's cells lie on.
    const int side_x_first = i >= x_hi ? 1 : 0, side_x_last = i <= x_lo ? 0 : 1;
    const int side_y_first = j >= y_hi ? 1 : 0, side_y_last = j <= y_lo ? 0 : 1;
    double shallowest = 2.0, rise = kNone;
    for (int sx = side_x_first; sx <= side_x_last; ++sx)
      for (int sy = side_y_first; sy <= side_y_last; ++sy) {
        shallowest = std::min(shallowest, double(b.shallowest[2 * sx + sy]));
        rise = std::min(rise, double(b.rise[2 * sx + sy]));
      }
    if (!(shallowest < apex)) return kNone;
    const double far_x = std::max(i - x_lo, x_hi - i) / width_, far_y = std::max(j - y_lo, y_hi - j) / height_;
    if (!is_unbounded(first_ + cx0, first_ + cx1, first_ + cy0, first_ + cy1) && !(rise * rise < far_x * far_x + far_y * far_y))
      return kNone;
    const double dx = std::max({0.0, x_lo - i, i - x_hi}) / width_, dy = std::max({0.0, y_lo - j, j - y_hi}) / height_;
    const double distance = std::sqrt(dx * dx + dy * dy);
    double bound = std::max(distance, rise) / (apex - shallowest);
    if (node.level == 0 && distance == 0.0) bound = std::max(bound, 1.0 / double(b.gradient));
    return bound;
  }

  // Pushes a node that could beat the best so far.
  void push(std::vector<Node>& heap, Node node, int i, int j, double apex, double best) const {
    node.lower_bound = lower_bound(node, i, j, apex);
    if (!(node.lower_bound < best)) return;
    heap.push_back(node);
    std::push_heap(heap.begin(), heap.end());
  }

  // REPEAT: the images k tiles away are at least k - 1 uv from the apex, which lies in tile 0.
  void push_ring(std::vector<Node>& heap, int k, double apex, double best) const {
    const double bound = (k - 1) / (apex - shallowest_);
    if (!(bound < best)) return;
    heap.push_back({bound, -1, 0, 0, k, 0, false});
    std::push_heap(heap.begin(), heap.end());
  }

  ConeGeometry geometry_;
  const DepthMap& map_;
  bool repeat_;
  int first_;  // texel-centre coordinate of cell 0's left (top) edge: CLAMP's strips come first
  int cells_x_, cells_y_;
  int width_, height_;
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
  tbb::parallel_for(tbb::blocked_range<int>(0, map.height), [&](const tbb::blocked_range<int>& rows) {
    std::vector<Node> heap;
    Node hint{0, -2, 0, 0, 0, 0, false};
    for (int j = rows.begin(); j != rows.end(); ++j)
      for (int i = 0; i < map.width; ++i) {
        const double c = builder.ratio(i, j, heap, hint);
        cone.ratio[std::size_t(j) * std::size_t(map.width) + std::size_t(i)] = rounded_down(c);
      }
  });
  cone.texture = SamplerTexture(DepthMap{map.width, map.height, cone.ratio}, wrap);
  cone.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cone;
}

double cone_cell_bound(const DepthMap& map, Wrap wrap, int i, int j, int cell_x, int cell_y) {
  const int tile_x = wrap == Wrap::repeat ? int(std::floor(double(cell_x) / map.width)) : 0;
  const int tile_y = wrap == Wrap::repeat ? int(std::floor(double(cell_y) / map.height)) : 0;
  return ConeGeometry(map, wrap).cell_bound(i, j, cell_x - tile_x * map.width, cell_y - tile_y * map.height, tile_x, tile_y);
}

std::shared_ptr<const ConeMap> cached_cone_map(const DepthMap& map, Wrap wrap) {
  static std::mutex mutex;
  static std::vector<std::shared_ptr<const ConeMap>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  for (const auto& cone : cache)
    if (cone->wrap == wrap && cone->width == map.width && cone->height == map.height && cone->depth == map.texels)
      return cone;
  cache.push_back(std::make_shared<const ConeMap>(build_cone_map(map, wrap)));
  return cache.back();
}

}  // namespace heightmarch
