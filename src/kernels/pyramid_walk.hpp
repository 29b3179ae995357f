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
#include <bit>
#include <limits>

#include "heightmarch/min_depth_pyramid.hpp"
#include "heightmarch/technique.hpp"
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

// A range's rays are queued, then walked in one of two schedules, chosen per ISA (its row of
// cmake/isa_list.cmake), whichever is faster there (docs/performance.md); a ray's outcome is the
// same under both.
//
// refill (PyramidWalker::run) keeps every lane busy (the persistent threads of Aila and Laine
// 2009, and the ray streams of Wald et al. and Embree, on SIMD lanes): a walk's pass reads a
// pyramid entry, and a cell it may touch waits for a solve that reads four texels, so the two run
// apart, each on full packets. A lane walks a ray from a queue until it needs a cell solved (the
// lane hands it to a list), has ended (clear beyond depth 1, or cut off by its bound: it leaves
// its outcome), and takes the queue's next ray at the next pass. The list is then solved a packet
// at a time; a ray whose path clears its cell goes on into the next round's queue. A lane computes
// the same for its ray whichever lane it is and whenever it starts. The outcomes are kept in the
// order the walks ended, with each ray's position, from which the caller makes the hits a packet
// at a time in ray order (src/isa/kernel_table.hpp, trace_walks).
//
// packet (PyramidWalker::walk_packet) walks each packet's rays in its own lanes to the last, a
// cell solved in the pass that reaches it: no moves and no lists, but idle lanes.
//
// The queues hold rays as the lanes do, a field a column.
enum class WalkSchedule { refill, packet };

inline constexpr int kWalkQueueRays = 1024;   // a tile of the default 32 x 32 pixels
inline constexpr int kWalkQueuePadding = 32;  // the widest packet: a pair of 16
inline constexpr int kWalkQueueSize = kWalkQueueRays + kWalkQueuePadding;

// 0, 1, 2, ...: queue positions, for the lanes that take them.
struct WalkQueuePositions {
  alignas(64) float values[kWalkQueueSize] = {};
  constexpr WalkQueuePositions() {
    for (int i = 0; i < kWalkQueueSize; ++i) values[i] = float(i);
  }
};
inline constexpr WalkQueuePositions kWalkQueuePositions{};

// How a ray's walk ended.
enum class WalkEnd { clear = 0, reached = 1, cut_off = 2 };

// A queue of rays as the lanes hold them (the ray's index in the range, its path, where its walk
// is); whole packets are read and written past its last ray.
struct WalkQueue {
  enum Field { x0, y0, dx, dy, inv_dx, inv_dy, eta, left, t, cx, cy, kFields };
  alignas(64) float column[kFields][kWalkQueueSize];
  alignas(64) std::int32_t ray[kWalkQueueSize], level[kWalkQueueSize], samples[kWalkQueueSize];

  // Rays [n, n + padding) read as zeros.
  void end_at(int n) {
    for (float* c : column) std::fill(c + n, c + n + kWalkQueuePadding, 0.0f);
    for (std::int32_t* c : {ray, level, samples}) std::fill(c + n, c + n + kWalkQueuePadding, 0);
  }
};

// A walk-shaped technique's first step (KernelShape::walk, technique_list.hpp), specialised in its
// kernel header: whether its walk is conservative, and queue(k, ray, queue, i), which queues a
// packet's walks; its kernel then makes the hits from their outcomes. Empty for a march.
template <Technique T>
struct WalkSteps {};

// The rays' outcomes in the order their walks ended (`where` each ray's): the depth at which it
// entered the cell it stopped in (or, cut off by the bound, the depth it had cleared), that cell,
// and the cell's quadratic over its span (c0, c1, c2, span) or, for the conservative walk, its
// texels (t00, t10, t01, t11); 0 for a ray that reached no cell.
struct WalkOutcomes {
  alignas(64) float t[kWalkQueueSize], cx[kWalkQueueSize], cy[kWalkQueueSize], end[kWalkQueueSize];
  alignas(64) float cell[4][kWalkQueueSize];
  alignas(64) std::int32_t samples[kWalkQueueSize];
  alignas(64) std::int32_t where[kWalkQueueRays];
  int count = 0;
};

// The outcome of one packet of rays, as the techniques read it.
template <int W>
struct PyramidWalk {
  vfloat<W> t;
  vfloat<W> cx, cy;              // the cell it stopped in
  vfloat<W> c0, c1, c2, span;    // its quadratic (the walk that is not conservative)
  vfloat<W> t00, t10, t01, t11;  // its texels (the conservative walk)
  vbool<W> reached;              // stopped in a cell it may touch
  vbool<W> cut_off;              // stopped by the bound on passes
  vint<W> samples;

  // Rays i .. i + W - 1.
  static PyramidWalk at(const WalkOutcomes& out, int i) {
    using F = vfloat<W>;
    const vint<W> at = vint<W>::load(out.where + i);
    PyramidWalk walk;
    walk.t = gather(out.t, at);
    walk.cx = gather(out.cx, at);
    walk.cy = gather(out.cy, at);
    walk.c0 = walk.t00 = gather(out.cell[0], at);
    walk.c1 = walk.t10 = gather(out.cell[1], at);
    walk.c2 = walk.t01 = gather(out.cell[2], at);
    walk.span = walk.t11 = gather(out.cell[3], at);
    const F end = gather(out.end, at);
    walk.reached = !(end != F(float(WalkEnd::reached)));
    walk.cut_off = !(end != F(float(WalkEnd::cut_off)));
    walk.samples = gather(out.samples, at);
    return walk;
  }
};

// A cell index clamped to [-1, n - 1] (CLAMP: the edge cells repeat the edge texels); REPEAT
// wraps where it reads.
template <Addressing ADDRESSING, int W>
vfloat<W> clamp_cell(vfloat<W> c, vfloat<W> n) {
  if constexpr (ADDRESSING != Addressing::clamp) return c;
  return min(max(c, vfloat<W>(-1.0f)), n - vfloat<W>(1.0f));
}

// At most this many passes a lane, so that its count stays exact in float. (Only a path of more
// than 2^18 cells, far beyond the default view's, has a larger bound below.)
inline constexpr float kMaxLanePasses = float((1 << 24) - 1);

// Queues the walks of rays i .. i + W - 1 (their index in the range) along the path
// (x0 + dx t, y0 + dy t); eta: the conservative walk's margin (0 otherwise).
template <int W, Addressing ADDRESSING>
void queue_walk(const KernelContext<W, ADDRESSING>& k, vfloat<W> x0, vfloat<W> y0, vfloat<W> dx, vfloat<W> dy,
                vfloat<W> eta, WalkQueue& q, int i) {
  using F = vfloat<W>;
  const int top = k.texture.min_depth_pyramid.levels - 1;  // -1: no interior cell (CLAMP, one texel wide)
  const F width(float(k.texture.width)), height(float(k.texture.height));
  const auto put = [&](WalkQueue::Field field, F value) { value.store(q.column[field] + i); };
  to_int(F::load(kWalkQueuePositions.values + i)).store(q.ray + i);
  put(WalkQueue::x0, x0);
  put(WalkQueue::y0, y0);
  put(WalkQueue::dx, dx);
  put(WalkQueue::dy, dy);
  put(WalkQueue::eta, eta);
  // A path parallel to an axis (dx = +0: the callers compute 0 - p, never -0) exits on the
  // high side at infinity.
  put(WalkQueue::inv_dx, F(1.0f) / dx);
  put(WalkQueue::inv_dy, F(1.0f) / dy);
  put(WalkQueue::cx, clamp_cell<ADDRESSING>(floor_to_cell(x0, dx), width));
  put(WalkQueue::cy, clamp_cell<ADDRESSING>(floor_to_cell(y0, dy), height));
  // Start where a block is about an eighth of the path's extent: the levels above it would
  // almost always be descended again, those below it climbed.
  const F extent = abs(dx) + abs(dy);
  vint<W> level(0);
  for (int l = 1; l <= top; ++l) level = select(extent >= F(float(1 << (l + 3))), vint<W>(l), level);
  level.store(q.level + i);
  // Each pass advances t or descends a level: the cells on the path times the levels bound it.
  // The passes left after the first: the pass p > bound (an integer) is past it.
  put(WalkQueue::left, floor(min(F(float(2 * (top + 2))) * (extent + F(2.0f)), F(kMaxLanePasses))));
  put(WalkQueue::t, F(0.0f));
  vint<W>(0).store(q.samples + i);
}

// The pyramid walk of maximum-mipmap tracing over a queue of rays. CONSERVATIVE (the exact
// reference's float pass): every test is loosened by the margin eta, which bounds the walk's
// rounding, so that a lane stops no later than the first cell the exact path touches
// (docs/conventions.md, the exact intersection).
template <bool CONSERVATIVE, int W, Addressing ADDRESSING>
class PyramidWalker {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  static constexpr bool kRepeat = ADDRESSING != Addressing::clamp;

  explicit PyramidWalker(KernelContext<W, ADDRESSING>& k)
      : k_(k),
        texture_(k.texture),
        width_(float(k.texture.width)),
        height_(float(k.texture.height)),
        inv_width_(1.0f / float(k.texture.width)),
        inv_height_(1.0f / float(k.texture.height)),
        top_(k.texture.min_depth_pyramid.levels - 1),
        top_level_(top_ < 0 ? 0 : top_) {
    // Per level: where its entries start (MinDepthPyramid's layout) and its blocks a side
    // (ceil(cells / 2^L)), looked up by each lane's level (register permutes where the ISA has
    // them) rather than carried along in selects at every change of level.
    static_assert(MinDepthPyramid::kMaxLevels <= 16, "the per-level tables are Table16s");
    const int last_cell_x = kRepeat ? texture_.width - 1 : texture_.width - 2;
    for (int l = 0; l <= std::max(top_, 0); ++l) {
      level_offset_.values[l] = top_ < 0 ? 0 : texture_.min_depth_pyramid.level_offsets[l];
      level_blocks_x_.values[l] = (last_cell_x >> l) + 1;
    }
  }

  // Walks the queued rays [0, n) of `rays` to their ends in rounds of walks and solves, leaving
  // their outcomes; `list` and `again` are scratch.
  void run(WalkQueue& rays, WalkQueue& list, WalkQueue& again, int n, WalkOutcomes& out) {
    out.count = 0;
    // Each round takes a pass of every ray it walks: within a lane's bound of passes.
    for (int round = 0; n > 0 && round <= int(kMaxLanePasses); ++round) {
      n = walk(round == 0 ? rays : again, n, list, out);
      n = solve(rays, list, n, again, out);
    }
  }

  // Walks the queued rays i .. i + W - 1 of `rays` in the packet's own lanes, each cell solved in
  // the pass that reaches it: no queue, no outcome lists, every lane's state in registers, but a
  // lane whose ray has ended idles until the packet's last has.
  PyramidWalk<W> walk_packet(const WalkQueue& rays, int i) {
    const auto field = [&](WalkQueue::Field f) { return F::load(rays.column[f] + i); };
    Lanes l = lanes(field, field, rays, i);
    PyramidWalk<W> walk;
    walk.c0 = walk.c1 = walk.c2 = walk.span = F(0.0f);
    walk.reached = walk.cut_off = !B::all_true();
    B live = B::all_true();
    // A lane is over its bound of passes (at most kMaxLanePasses) by the pass after it.
    for (std::int64_t p = 0; p <= std::int64_t(kMaxLanePasses) && any(live); ++p) {
      l.left = select(live, l.left - F(1.0f), l.left);
      const B over = live & (l.left < F(0.0f));
      const Pass s = pass(l, live & !over);
      B hit = !B::all_true();
      if (any(s.solve)) {
        F cell[4];
        hit = test_cell(l, s.box, s.solve, cell);
        walk.c0 = select(hit, cell[0], walk.c0);
        walk.c1 = select(hit, cell[1], walk.c1);
        walk.c2 = select(hit, cell[2], walk.c2);
        walk.span = select(hit, cell[3], walk.span);
      }
      const B beyond = advance(l, s.box, s.skip | (s.solve & !hit), s.descend, s.clear_above);
      walk.reached = walk.reached | hit;
      walk.cut_off = walk.cut_off | over;
      live = live & !(over | beyond | hit);
    }
    walk.t00 = walk.c0;
    walk.t10 = walk.c1;
    walk.t01 = walk.c2;
    walk.t11 = walk.span;
    walk.t = l.t;
    walk.cx = l.cx;
    walk.cy = l.cy;
    walk.samples = l.samples;
    return walk;
  }

 private:
  // Rays in lanes: a queue's fields as packets.
  struct Lanes {
    I ray;
    F x0, y0, dx, dy, inv_dx, inv_dy, eta, left, t, cx, cy;
    I level, samples;
  };

  // A packet of lanes (but its rays' indices): the paths' fields from path(field), where the
  // walks are from walk(field) and from q's packet at i.
  template <class Path, class Walk>
  static Lanes lanes(Path path, Walk walk, const WalkQueue& q, int i) {
    Lanes l;
    l.x0 = path(WalkQueue::x0);
    l.y0 = path(WalkQueue::y0);
    l.dx = path(WalkQueue::dx);
    l.dy = path(WalkQueue::dy);
    l.inv_dx = path(WalkQueue::inv_dx);
    l.inv_dy = path(WalkQueue::inv_dy);
    l.eta = CONSERVATIVE ? path(WalkQueue::eta) : F(0.0f);
    l.left = walk(WalkQueue::left);
    l.t = walk(WalkQueue::t);
    l.cx = walk(WalkQueue::cx);
    l.cy = walk(WalkQueue::cy);
    l.level = I::load(q.level + i);
    l.samples = I::load(q.samples + i);
    return l;
  }

  // The box a lane is in: its block at its level (blocks tile the period: REPEAT keeps a level
  // only while 2^L divides both sides), or (CLAMP edge cells) the cell, infinite on its outer
  // side; where the path leaves it (tx, ty, te) and where the lane's span ends (t_end).
  struct Box {
    B interior, high_x, high_y;
    F size, inv_size, bx, by;  // bx, by: the block, unwrapped
    F x_lo, x_hi, y_lo, y_hi, tx, ty, te, t_end;
  };

  Box box(const Lanes& l) const {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Box b;
    b.high_x = !(l.dx < F(0.0f));
    b.high_y = !(l.dy < F(0.0f));
    b.interior = B::all_true();
    if constexpr (!kRepeat)
      b.interior =
          (l.cx >= F(0.0f)) & (l.cx < width_ - F(1.0f)) & (l.cy >= F(0.0f)) & (l.cy < height_ - F(1.0f));
    b.size = pow2(l.level);
    b.inv_size = pow2(I(0) - l.level);
    b.bx = floor(l.cx * b.inv_size);
    b.by = floor(l.cy * b.inv_size);
    b.x_lo = b.bx * b.size;
    b.y_lo = b.by * b.size;
    b.x_hi = b.x_lo + b.size;
    b.y_hi = b.y_lo + b.size;
    if constexpr (!kRepeat) {
      b.x_hi = min(b.x_hi, width_ - F(1.0f));
      b.y_hi = min(b.y_hi, height_ - F(1.0f));
      b.x_lo = select(b.interior, b.x_lo, select(l.cx < F(0.0f), F(-kInf), l.cx));
      b.x_hi = select(b.interior, b.x_hi, select(l.cx >= width_ - F(1.0f), F(kInf), l.cx + F(1.0f)));
      b.y_lo = select(b.interior, b.y_lo, select(l.cy < F(0.0f), F(-kInf), l.cy));
      b.y_hi = select(b.interior, b.y_hi, select(l.cy >= height_ - F(1.0f), F(kInf), l.cy + F(1.0f)));
    }
    b.tx = (select(b.high_x, b.x_hi, b.x_lo) - l.x0) * l.inv_dx;
    b.ty = (select(b.high_y, b.y_hi, b.y_lo) - l.y0) * l.inv_dy;
    b.te = min(b.tx, b.ty);
    b.t_end = min(b.te, F(1.0f));
    return b;
  }

  // Leaving the box (leave: without a hit): no hit at all past depth 1 (the lanes returned),
  // else into the next box. Descending: nothing in the block is met before the path reaches its
  // shallowest depth, clear_above.
  B advance(Lanes& l, const Box& b, B leave, B descend, F clear_above) const {
    const B beyond = leave & !(b.te < F(1.0f));
    const B move = leave & !beyond;
    const B reach = descend & (clear_above > l.t);
    const F t_next = select(move, b.te, min(clear_above, b.t_end));
    const F at_x = min(max(floor_to_cell(l.x0 + l.dx * t_next, l.dx), b.x_lo), b.x_hi - F(1.0f));
    const F at_y = min(max(floor_to_cell(l.y0 + l.dy * t_next, l.dy), b.y_lo), b.y_hi - F(1.0f));
    const B exit_x = move & !(b.tx > b.ty), exit_y = move & !(b.ty > b.tx);
    const B step = move | reach;
    l.t = select(step, t_next, l.t);
    l.cx = select(
        step,
        clamp_cell<ADDRESSING>(select(exit_x, select(b.high_x, b.x_hi, b.x_lo - F(1.0f)), at_x), width_),
        l.cx);
    l.cy = select(
        step,
        clamp_cell<ADDRESSING>(select(exit_y, select(b.high_y, b.y_hi, b.y_lo - F(1.0f)), at_y), height_),
        l.cy);
    // Up a level only out of the block's parent: inside it the parent would be descended again.
    // The parent changes where the crossed side lies on a multiple of twice the block's side.
    const F half_inv = b.inv_size * F(0.5f);
    const F side_x = select(b.high_x, b.x_hi, b.x_lo) * half_inv;
    const F side_y = select(b.high_y, b.y_hi, b.y_lo) * half_inv;
    const B new_parent = (exit_x & !(floor(side_x) != side_x)) | (exit_y & !(floor(side_y) != side_y));
    const B up = move & new_parent & (l.level < top_level_);
    l.level = select(up, l.level + I(1), select(descend, l.level - I(1), l.level));
    return beyond;
  }

  // The free lanes of `live` take the queue's rays from `next` on, in lane order.
  void take(const WalkQueue& q, int n, int& next, Lanes& l, B& live) const {
    const B free = !live;
    const B taken = free & (expand_load(kWalkQueuePositions.values + next, free, F(0.0f)) < F(float(n)));
    const auto field = [&](WalkQueue::Field f, F old) { return expand_load(q.column[f] + next, taken, old); };
    l.ray = expand_load(q.ray + next, taken, l.ray);
    l.x0 = field(WalkQueue::x0, l.x0);
    l.y0 = field(WalkQueue::y0, l.y0);
    l.dx = field(WalkQueue::dx, l.dx);
    l.dy = field(WalkQueue::dy, l.dy);
    l.inv_dx = field(WalkQueue::inv_dx, l.inv_dx);
    l.inv_dy = field(WalkQueue::inv_dy, l.inv_dy);
    if constexpr (CONSERVATIVE) l.eta = field(WalkQueue::eta, l.eta);
    l.left = field(WalkQueue::left, l.left);
    l.t = field(WalkQueue::t, l.t);
    l.cx = field(WalkQueue::cx, l.cx);
    l.cy = field(WalkQueue::cy, l.cy);
    l.level = expand_load(q.level + next, taken, l.level);
    l.samples = expand_load(q.samples + next, taken, l.samples);
    live = live | taken;
    next += std::popcount(mask_bits(taken));
  }

  // Appends the lanes `leaving` to q at `at`: where their walks are, and (WITH_PATH) their paths.
  template <bool WITH_PATH>
  static void hand_over(const Lanes& l, B leaving, WalkQueue& q, int& at) {
    const auto field = [&](WalkQueue::Field f, F value) { compress_store(q.column[f] + at, leaving, value); };
    compress_store(q.ray + at, leaving, l.ray);
    if constexpr (WITH_PATH) {
      field(WalkQueue::x0, l.x0);
      field(WalkQueue::y0, l.y0);
      field(WalkQueue::dx, l.dx);
      field(WalkQueue::dy, l.dy);
      field(WalkQueue::inv_dx, l.inv_dx);
      field(WalkQueue::inv_dy, l.inv_dy);
      if constexpr (CONSERVATIVE) field(WalkQueue::eta, l.eta);
    }
    field(WalkQueue::left, l.left);
    field(WalkQueue::t, l.t);
    field(WalkQueue::cx, l.cx);
    field(WalkQueue::cy, l.cy);
    compress_store(q.level + at, leaving, l.level);
    compress_store(q.samples + at, leaving, l.samples);
    at += std::popcount(mask_bits(leaving));
  }

  // The outcomes of the lanes `ending`, their walks ended as `end` says, in the cell `cell`.
  static void leave_outcome(const Lanes& l, B ending, F end, const F (&cell)[4], WalkOutcomes& out) {
    const auto field = [&](float* column, F value) { compress_store(column + out.count, ending, value); };
    field(out.t, l.t);
    field(out.cx, l.cx);
    field(out.cy, l.cy);
    field(out.end, end);
    for (int c = 0; c < 4; ++c) field(out.cell[c], cell[c]);
    compress_store(out.samples + out.count, ending, l.samples);
    scatter(out.where, l.ray, ending,
            to_int(expand_load(kWalkQueuePositions.values + out.count, ending, F(0.0f))));
    out.count += std::popcount(mask_bits(ending));
  }

  // One pass of the lanes `active`: the box each is in, the pyramid entry of its block read, and
  // what the lane does next (skip the box, descend a level, or have its cell solved).
  struct Pass {
    Box box;
    F clear_above;  // the path is clear of the block above this depth
    B skip, descend, solve;
  };

  Pass pass(Lanes& l, B active) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Pass s;
    s.box = box(l);
    const Box& b = s.box;
    const B in_pyramid = active & b.interior & (top_ >= 0 ? B::all_true() : !B::all_true());
    F shallowest(-kInf);
    if (top_ >= 0) {
      // The block's entry; REPEAT wraps the block index into the level's nb blocks a side.
      F bx = b.bx, by = b.by;
      if constexpr (kRepeat) {
        const F nbx = width_ * b.inv_size, nby = height_ * b.inv_size;
        if constexpr (ADDRESSING == Addressing::repeat_pow2) {  // exact in float: no correction
          bx = bx - nbx * floor(bx * inv_width_ * b.size);
          by = by - nby * floor(by * inv_height_ * b.size);
        } else {
          bx = wrap_cell(bx, nbx, inv_width_ * b.size);
          by = wrap_cell(by, nby, inv_height_ * b.size);
        }
      }
      const I entry =
          lookup(level_offset_, l.level) + to_int(by) * lookup(level_blocks_x_, l.level) + to_int(bx);
      if constexpr (!CONSERVATIVE) k_.count(in_pyramid, l.samples, 1);
      shallowest = select(
          in_pyramid, gather(texture_.min_depth_pyramid.texels, select(in_pyramid, entry, I(0))), F(-kInf));
    }
    s.clear_above = shallowest;
    if constexpr (CONSERVATIVE) s.clear_above = s.clear_above - l.eta;
    s.skip = in_pyramid & (b.t_end < s.clear_above);
    s.descend = in_pyramid & (!s.skip) & (I(0) < l.level);
    s.solve = active & (!s.skip) & (!s.descend);
    return s;
  }

  // The cell test of the lanes `solving`: whether the path meets the patch of its cell before it
  // leaves the box. Where it does, `cell` holds the quadratic over the span, or (CONSERVATIVE:
  // the exact reference solves the cell again in double) the texels; 0 elsewhere.
  B test_cell(Lanes& l, const Box& b, B solving, F (&cell)[4]) {
    F t00, t10, t01, t11;
    cell_texels<ADDRESSING>(texture_, l.cx, l.cy, t00, t10, t01, t11);
    k_.count(solving, l.samples, CONSERVATIVE ? 1 : 4);
    const F fx = (l.x0 - l.cx) + l.dx * l.t, fy = (l.y0 - l.cy) + l.dy * l.t;
    const F e = t10 - t00, f = t01 - t00, g = (t11 - t10) - (t01 - t00);
    const F c0 = l.t - (t00 + e * fx + f * fy + g * fx * fy) + l.eta;
    const F c1 = F(1.0f) - (e * l.dx + f * l.dy + g * (fx * l.dy + fy * l.dx));
    const F c2 = F(0.0f) - g * l.dx * l.dy;
    const F span = b.t_end - l.t;
    const B hit = solving & reaches_patch(c0, c1, c2, span);
    const F zero(0.0f);
    cell[0] = select(hit, CONSERVATIVE ? t00 : c0, zero);
    cell[1] = select(hit, CONSERVATIVE ? t10 : c1, zero);
    cell[2] = select(hit, CONSERVATIVE ? t01 : c2, zero);
    cell[3] = select(hit, CONSERVATIVE ? t11 : span, zero);
    return hit;
  }

  // Walks the n rays of q until each has ended or needs a solve, then handed to `list` (at its
  // positions 0, 1, ...; returns how many). A lane takes the next ray as soon as its own leaves.
  int walk(WalkQueue& q, int n, WalkQueue& list, WalkOutcomes& out) {
    q.end_at(n);
    Lanes l{};
    l.level = l.samples = I(0);
    B live = !B::all_true();
    int next = 0, listed = 0;
    take(q, n, next, l, live);
    // Every ray ends its walk within its bound: the round within n times that.
    const std::int64_t max_passes = std::int64_t(n) * (std::int64_t(kMaxLanePasses) + 2);
    for (std::int64_t p = 0; p < max_passes && any(live); ++p) {
      // Past its bound a lane stops where it is, its path clear down to t (cut off).
      l.left = select(live, l.left - F(1.0f), l.left);
      const B over = live & (l.left < F(0.0f));
      const Pass s = pass(l, live & !over);
      const B beyond = advance(l, s.box, s.skip, s.descend, s.clear_above);

      const B ended = over | beyond;
      if (any(ended | s.solve)) {
        if (any(ended)) {
          const F no_cell[4] = {F(0.0f), F(0.0f), F(0.0f), F(0.0f)};
          leave_outcome(l, ended, select(over, F(float(WalkEnd::cut_off)), F(float(WalkEnd::clear))), no_cell,
                        out);
        }
        hand_over<false>(l, s.solve, list, listed);
        live = live & !(ended | s.solve);
        if (next < n) take(q, n, next, l, live);
      }
    }
    return listed;
  }

  // Solves the cells of the n rays of `list`, a packet at a time (their paths read from `rays` at
  // their indices): each ray whose walk ends there leaves its outcome, the others go on into
  // `again` to walk on. Returns how many.
  int solve(const WalkQueue& rays, WalkQueue& list, int n, WalkQueue& again, WalkOutcomes& out) {
    list.end_at(n);
    int kept = 0;
    for (int i = 0; i < n; i += W) {
      const I ray = I::load(list.ray + i);
      const auto path = [&](WalkQueue::Field f) { return gather(rays.column[f], ray); };
      const auto field = [&](WalkQueue::Field f) { return F::load(list.column[f] + i); };
      Lanes l = lanes(path, field, list, i);
      l.ray = ray;
      const B solving = F::load(kWalkQueuePositions.values) < F(float(n - i));  // lane < n - i
      const Box b = box(l);
      F cell[4];
      const B hit = test_cell(l, b, solving, cell);
      const B beyond = advance(l, b, solving & !hit, !B::all_true(), F(0.0f));
      leave_outcome(l, hit | beyond, select(hit, F(float(WalkEnd::reached)), F(float(WalkEnd::clear))), cell,
                    out);
      hand_over<true>(l, solving & !hit & !beyond, again, kept);
    }
    return kept;
  }

  KernelContext<W, ADDRESSING>& k_;
  const KernelTexture& texture_;
  const F width_, height_, inv_width_, inv_height_;
  const int top_;  // -1: no interior cell (CLAMP, one texel wide)
  const I top_level_;
  Table16<std::int32_t> level_offset_, level_blocks_x_;
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
