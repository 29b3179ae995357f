// The exact hit on the surface a ray reads: the trilinear blend of two mip levels at its level of
// detail, walked and solved as the exact reference walks and solves level 0 (cell_walk.hpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "exact/cell_walk.hpp"
#include "heightmarch/exact.hpp"
#include "heightmarch/mip_chain.hpp"

namespace heightmarch {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The blend's bound is a + f (b - a) of two floats, rounded in double: lowered by this much, it
// stays below the blend wherever the path may touch it (depths lie in [0, 1]).
constexpr double kBoundMargin = 1e-12;

// A bound below level b's bilinear surface over each cell of level a's grid (cells_x x cells_y,
// the cells its pyramid covers): the shallowest texel of the b cells that overlap the cell's
// texture coordinates. Level b's texel coordinate is x_b = (x_a + 0.5) r - 0.5, r = W_b / W_a.
std::vector<float> coarser_level_below(const DepthMap& a, const DepthMap& b, Wrap wrap, int cells_x,
                                       int cells_y) {
  const double rx = double(b.width) / double(a.width), ry = double(b.height) / double(a.height);
  // The b cells [first, last] over a's cell c (its coordinates c to c + 1).
  const auto span = [](long long c, double r) {
    const double lo = (double(c) + 0.5) * r - 0.5, hi = (double(c) + 1.5) * r - 0.5;
    return std::pair{(long long)std::floor(lo),
                     std::max((long long)std::floor(lo), (long long)std::ceil(hi) - 1)};
  };
  std::vector<float> below(std::size_t(cells_x) * std::size_t(cells_y));
  for (int j = 0; j < cells_y; ++j) {
    const auto [y0, y1] = span(j, ry);
    for (int i = 0; i < cells_x; ++i) {
      const auto [x0, x1] = span(i, rx);
      double m = kInf;
      for (long long y = y0; y <= y1 + 1; ++y)
        for (long long x = x0; x <= x1 + 1; ++x) m = std::min(m, wrapped_texel(b, wrap, x, y));
      below[std::size_t(j) * std::size_t(cells_x) + std::size_t(i)] = float(m);
    }
  }
  return below;
}

// The surface a + f (b - a) of two levels a and b (b the next, coarser one) as the walk solves it,
// in level a's texel coordinates: its cells are a's, each cut where b's cells begin, and each piece
// is bilinear in the cell's coordinates, so it is solved as a cell of level 0 is.
struct BlendCells {
  const DepthMap& a;
  const DepthMap& b;
  Wrap wrap;
  const MinDepthPyramid& a_below;  // a's own pyramid
  const MinDepthPyramid& b_below;  // b's bound over a's cells, reduced alike
  double f;                        // the blend weight, in (0, 1)

  long long width() const { return a.width; }
  long long height() const { return a.height; }
  bool repeat() const { return wrap == Wrap::repeat; }
  int top_level() const { return a_below.levels() - 1; }
  double shallowest(int level, long long bx, long long by) const {
    const double lo_a = a_below.at(level, bx, by), lo_b = b_below.at(level, bx, by);
    return lo_a + f * (lo_b - lo_a) - kBoundMargin;
  }

  bool solve_cell(long long ci, long long cj, const HeightfieldPath& p, double t0, double t1,
                  double& t_hit) const {
    // Level a over the cell, as c + e fx + g fy + h fx fy in the cell's coordinates (fx, fy).
    const double a00 = wrapped_texel(a, wrap, ci, cj), a10 = wrapped_texel(a, wrap, ci + 1, cj);
    const double a01 = wrapped_texel(a, wrap, ci, cj + 1), a11 = wrapped_texel(a, wrap, ci + 1, cj + 1);
    const double ae = a10 - a00, ag = a01 - a00, ah = a11 - a10 - a01 + a00;
    // The path in level b's texel coordinates, and b's cells along it (a clamp edge cell reaches to
    // infinity on its outer side).
    const double rx = double(b.width) / double(a.width), ry = double(b.height) / double(a.height);
    const double bx0 = (p.x0 + 0.5) * rx - 0.5, bdx = p.dx * rx;
    const double by0 = (p.y0 + 0.5) * ry - 0.5, bdy = p.dy * ry;
    const bool repeat_b = wrap == Wrap::repeat;
    const auto b_cell = [&](double x, double rate, long long n) {
      const long long c = floor_to_cell(x, rate);
      return repeat_b ? c : std::clamp(c, -1LL, n - 1);
    };
    const auto b_exit = [&](long long c, double origin, double rate, long long n) {
      if (rate > 0.0 && (repeat_b || c < n - 1)) return (double(c + 1) - origin) / rate;
      if (rate < 0.0 && (repeat_b || c > -1)) return (double(c) - origin) / rate;
      return kInf;
    };
    double t = t0;
    long long kx = b_cell(bx0 + bdx * t, bdx, b.width), ky = b_cell(by0 + bdy * t, bdy, b.height);
    // Pieces: one more than the b cell sides the path crosses within the cell, at most.
    const double pieces = 4.0 + (std::fabs(bdx) + std::fabs(bdy)) * (t1 - t0);
    for (double piece = 0; piece < pieces; ++piece) {
      const double tx = b_exit(kx, bx0, bdx, b.width), ty = b_exit(ky, by0, bdy, b.height);
      const double te = std::max(t, std::min({t1, tx, ty}));
      // Level b over this piece, in the same cell coordinates: b's own (gx, gy) = (r fx + ox, r fy + oy).
      const double b00 = wrapped_texel(b, wrap, kx, ky), b10 = wrapped_texel(b, wrap, kx + 1, ky);
      const double b01 = wrapped_texel(b, wrap, kx, ky + 1), b11 = wrapped_texel(b, wrap, kx + 1, ky + 1);
      const double be = b10 - b00, bg = b01 - b00, bh = b11 - b10 - b01 + b00;
      const double ox = (double(ci) + 0.5) * rx - 0.5 - double(kx),
                   oy = (double(cj) + 0.5) * ry - 0.5 - double(ky);
      const double bc = b00 + be * ox + bg * oy + bh * ox * oy;
      const double bx = (be + bh * oy) * rx, by = (bg + bh * ox) * ry, bxy = bh * rx * ry;
      // The blend, as the corners of a cell (its bilinear extended to them).
      const double c = a00 + f * (bc - a00), e = ae + f * (bx - ae), g = ag + f * (by - ag),
                   h = ah + f * (bxy - ah);
      const CellQuadratic<double> q = cell_quadratic(c, c + e, c + g, c + e + g + h, double(ci), double(cj),
                                                     p.x0, p.y0, p.dx, p.dy, p.depth0, p.ddepth, t);
      double s;
      if (first_root(q, te - t, s)) {
        t_hit = t + s;
        return true;
      }
      if (te >= t1) return false;
      const auto step = [&](long long c, double rate, long long n) {
        c += rate > 0.0 ? 1 : -1;
        return repeat_b ? c : std::clamp(c, -1LL, n - 1);
      };
      if (tx <= ty) kx = step(kx, bdx, b.width);
      if (ty <= tx) ky = step(ky, bdy, b.height);
      t = te;
    }
    return false;
  }
};

}  // namespace

// The mip chain, an intersector per level (its own pyramid) and, per pair of levels, level b's
// bound over level a's cells.
struct FilteredExactReference::Levels {
  std::vector<DepthMap> chain;
  std::vector<std::unique_ptr<ExactIntersector>> exact;  // by level; each keeps a pointer into chain
  std::vector<MinDepthPyramid> next_below;               // by level a, of level a + 1

  Levels(const DepthMap& map, Wrap wrap) : chain(build_mip_chain(map)) {
    for (const DepthMap& level : chain) exact.push_back(std::make_unique<ExactIntersector>(level, wrap));
    for (std::size_t a = 0; a + 1 < chain.size(); ++a) {
      const bool repeat = wrap == Wrap::repeat;
      const int cells_x = repeat ? chain[a].width : chain[a].width - 1;
      const int cells_y = repeat ? chain[a].height : chain[a].height - 1;
      next_below.emplace_back(cells_x, cells_y, wrap,
                              cells_x < 1 || cells_y < 1
                                  ? std::vector<float>{}
                                  : coarser_level_below(chain[a], chain[a + 1], wrap, cells_x, cells_y));
    }
  }
};

FilteredExactReference::FilteredExactReference(const DepthMap& map, const TechniqueParams& params)
    : map_(&map), params_(params), levels_(std::make_unique<Levels>(map, params.wrap)) {}

FilteredExactReference::~FilteredExactReference() = default;

PathHit FilteredExactReference::intersect(double tx, double ty, double vx, double vy, double vz,
                                          float lod) const {
  const double s = params_.scale;
  const int last = int(levels_->chain.size()) - 1;
  const int first = std::clamp(int(std::floor(lod)), 0, last);
  const double f = double(lod) - double(first);
  if (f <= 0.0 || first == last) return levels_->exact[std::size_t(first)]->intersect(tx, ty, vx, vy, vz, s);
  const DepthMap &a = levels_->chain[std::size_t(first)], &b = levels_->chain[std::size_t(first) + 1];
  const BlendCells blend{a,
                         b,
                         params_.wrap,
                         levels_->exact[std::size_t(first)]->pyramid(),
                         levels_->next_below[std::size_t(first)],
                         f};
  PathHit hit = walk_cells(blend, ray_path(tx, ty, vx, vy, vz, s, a.width, a.height), 0.0);
  if (!hit.found) {  // only rounding can get here: the blend <= 1 guarantees a hit by depth 1
    hit.found = true;
    hit.t = 1.0;
  }
  return hit;
}

void FilteredExactReference::run(const RayBatch& rays, const HitBuffers& level0, HitBuffers& hits) const {
  hits = level0;
  if (params_.filter_read() != Filter::trilinear) return;
  check_exact_path_lengths(*map_, rays, params_);
  const int last = int(levels_->chain.size()) - 1;
  const double s = params_.scale;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1),
      [&](const tbb::blocked_range<std::size_t>& tiles) {
        for (std::size_t t = tiles.begin(); t != tiles.end(); ++t)
          for (std::size_t i = rays.tile_offsets[t]; i < rays.tile_offsets[t + 1]; ++i) {
            if (rays.is_padding(i)) continue;
            const float lod = level_of_detail(rays.du_dx[i], rays.dv_dx[i], rays.du_dy[i], rays.dv_dy[i],
                                              float(map_->width), float(map_->height), last);
            if (lod <= 0.0f) continue;  // level 0: the exact reference's hit
            const PathHit hit = intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], lod);
            const double d = hit.t, offset_per_depth = s / double(rays.vz[i]);
            const double u = rays.tx[i] - d * offset_per_depth * rays.vx[i];
            const double v = rays.ty[i] - d * offset_per_depth * rays.vy[i];
            hits.u[i] = float(u);
            hits.v[i] = float(v);
            hits.depth[i] = float(d);
            hits.samples[i] = hit.cells;
            hits.discarded[i] = params_.discard && (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0);
          }
      });
}

}  // namespace heightmarch
