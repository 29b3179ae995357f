#pragma once
// The min-depth pyramid walk of maximum-mipmap tracing (Tevs, Ihrke and Seidel 2008; Drobot's
// quadtree displacement mapping is the same walk): the ray goes down the min-depth pyramid while it
// may touch a block's shallowest texel and back up after it leaves a block's parent without a hit;
// in a cell it may touch, it tests the bilinear patch's quadratic in float.
//
// In texel space x = u W - 0.5 the ray is x(t) = x0 + dx t at depth t (dx = -s V.x / V.z W), as
// in the exact reference, whose double walk (src/exact/exact_intersector.cpp) takes the same
// steps. A sample is one texel read: one per pyramid entry, four per tested cell.
//
// Each ray is walked mirrored: an axis along which it runs towards -x is negated (x -> -x, cell
// c -> ~c = -c - 1, block b -> ~b at every level, REPEAT's wrap included), so that it always
// leaves a box by its high sides and a box is a plain shift of its cell. Negation is exact in
// float, so every time, position and cell is the unmirrored walk's, bit for bit (cells exactly
// below 2^24, as the walk's floats); its cells and blocks are integers.
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

// A cell index wrapped into [0, n - 1] (REPEAT), in float as the sampler wraps sides that are not
// powers of two (exact below 2^24).
template <int W>
vfloat<W> wrap_cell(vfloat<W> c, vfloat<W> n, vfloat<W> inv_n) {
  using F = vfloat<W>;
  F r = c - n * floor(c * inv_n);
  r = select(r < F(0.0f), r + n, r);
  r = select(r >= n, r - n, r);
  return min(max(r, F(0.0f)), n - F(1.0f));
}

// The four texels of cell (cx, cy) (CLAMP's edge cells repeat the edge texels).
template <Addressing ADDRESSING, int W>
void cell_texels(const KernelTexture& texture, vint<W> cx, vint<W> cy, vfloat<W>& t00, vfloat<W>& t10,
                 vfloat<W>& t01, vfloat<W>& t11) {
  using F = vfloat<W>;
  using I = vint<W>;
  const I last_x(texture.width - 1), last_y(texture.height - 1);
  I ix, iy;
  if constexpr (ADDRESSING == Addressing::repeat_pow2) {
    ix = cx & last_x;
    iy = cy & last_y;
  } else if constexpr (ADDRESSING == Addressing::repeat) {
    const F width(float(texture.width)), height(float(texture.height));
    ix = min(to_int(wrap_cell(to_float(cx), width, F(1.0f / float(texture.width)))), last_x);
    iy = min(to_int(wrap_cell(to_float(cy), height, F(1.0f / float(texture.height)))), last_y);
  } else {
    ix = min(max(cx, I(0)), last_x);
    iy = min(max(cy, I(0)), last_y);
  }
  const I index = iy * I(texture.stride) + ix;
  gather_pairs(texture.texels, index, t00, t10);
  gather_pairs(texture.texels + texture.stride, index, t01, t11);
  if constexpr (ADDRESSING == Addressing::clamp) {
    const vbool<W> left = cx < I(0), above = cy < I(0);
    t10 = select(left, t00, t10);
    t11 = select(left, t01, t11);
    t01 = select(above, t00, t01);
    t11 = select(above, t10, t11);
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

// A range's rays are queued, then walked in the lanes of a packet (the persistent threads of Aila
// and Laine 2009, the ray streams of Wald et al. and Embree, on SIMD lanes): a lane walks its ray
// pass by pass, each pass reading one pyramid entry, until the ray has ended (clear beyond depth 1)
// or reaches a cell it may touch. Such a lane waits, passing without effect, until EVENT_LANES
// lanes wait (its ISA's, cmake/isa_list.cmake); then the waiting lanes' cells are solved at once
// (four texels and the quadratic), the rays that end there or are over their bound of passes leave
// their outcomes, and the free lanes take the queue's next rays. Solving and refilling a share of
// the packet at a time keeps that work off the common pass, whose state is a few registers a lane
// (the ray's constants stay in memory, one slot a lane). A lane computes the same for its ray
// whichever lane it is and whenever it starts. The outcomes are kept per ray, from which the
// caller makes the hits a packet at a time (src/isa/kernel_table.hpp, trace_walks).
inline constexpr int kWalkQueueRays = 1024;   // a tile of the default 32 x 32 pixels
inline constexpr int kWalkQueuePadding = 32;  // the widest packet: a pair of 16
inline constexpr int kWalkQueueSize = kWalkQueueRays + kWalkQueuePadding;

// 0, 1, 2, ...: queue positions, for the lanes that take them.
struct WalkQueuePositions {
  alignas(64) std::int32_t values[kWalkQueueSize] = {};
  constexpr WalkQueuePositions() {
    for (int i = 0; i < kWalkQueueSize; ++i) values[i] = i;
  }
};
inline constexpr WalkQueuePositions kWalkQueuePositions{};

// How a ray's walk ended.
enum class WalkEnd { clear = 0, reached = 1, cut_off = 2 };

// A queue of rays as the lanes hold them, a field a column; whole packets are read past its last
// ray. Each ray mirrored (flip_x, flip_y: -1 where an axis is negated, else 0): its path (x0, y0,
// dx >= 0, dy >= 0, 1 / dx, 1 / dy), the conservative walk's margin eta, the range of interior
// cells along each axis (CLAMP), where its walk starts (cell and level) and its bound on passes.
struct WalkQueue {
  enum Float { x0, y0, dx, dy, inv_dx, inv_dy, eta, kFloats };
  enum Int { flip_x, flip_y, low_x, high_x, low_y, high_y, bound, cell_x, cell_y, level, kInts };
  static constexpr int kConstantInts = bound + 1;  // the fields a lane keeps in memory
  alignas(64) float f[kFloats][kWalkQueueSize];
  alignas(64) std::int32_t i[kInts][kWalkQueueSize];

  // Rays [n, n + padding): no ray. A lane that takes one never moves: at level 0 its path starts
  // at -infinity, so that it never leaves its cell, and its pass always wants a solve.
  void end_at(int n) {
    for (int c = 0; c < kFloats; ++c) {
      const float value = c == x0 || c == y0 ? -std::numeric_limits<float>::infinity()
                          : c == eta         ? 0.0f
                                             : 1.0f;
      std::fill(f[c] + n, f[c] + n + kWalkQueuePadding, value);
    }
    for (std::int32_t* c : i) std::fill(c + n, c + n + kWalkQueuePadding, 0);
  }
};

// A walk-shaped technique's first step (KernelShape::walk, technique_list.hpp), specialised in its
// kernel header: whether its walk is conservative, and queue(k, ray, queue, i), which queues a
// packet's walks; its kernel then makes the hits from their outcomes. Empty for a march.
template <Technique T>
struct WalkSteps {};

// Each ray's outcome (at its queue position): the depth at which it entered the cell it stopped
// in (or, cut off by the bound, the depth it had cleared), how the walk ended, and the cell's
// quadratic over its span (c0, c1, c2, span) or, for the conservative walk, the cell and its
// texels (t00, t10, t01, t11); 0 for a ray that reached no cell.
struct WalkOutcomes {
  alignas(64) float t[kWalkQueueSize], cx[kWalkQueueSize], cy[kWalkQueueSize], end[kWalkQueueSize];
  alignas(64) float cell[4][kWalkQueueSize];
  alignas(64) std::int32_t samples[kWalkQueueSize];
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

  // Rays i .. i + W - 1 of the walk (CONSERVATIVE: the one that keeps the cells).
  template <bool CONSERVATIVE>
  static PyramidWalk at(const WalkOutcomes& out, int i) {
    using F = vfloat<W>;
    PyramidWalk walk;
    walk.t = F::load(out.t + i);
    walk.cx = CONSERVATIVE ? F::load(out.cx + i) : F(0.0f);
    walk.cy = CONSERVATIVE ? F::load(out.cy + i) : F(0.0f);
    walk.c0 = walk.t00 = F::load(out.cell[0] + i);
    walk.c1 = walk.t10 = F::load(out.cell[1] + i);
    walk.c2 = walk.t01 = F::load(out.cell[2] + i);
    walk.span = walk.t11 = F::load(out.cell[3] + i);
    const F end = F::load(out.end + i);
    walk.reached = !(end != F(float(WalkEnd::reached)));
    walk.cut_off = !(end != F(float(WalkEnd::cut_off)));
    walk.samples = vint<W>::load(out.samples + i);
    return walk;
  }
};

// At most this many passes a lane. (Only a path of more than 2^18 cells, far beyond the default
// view's, has a larger bound below.)
inline constexpr float kMaxLanePasses = float((1 << 24) - 1);

// Queues the walks of rays i .. i + W - 1 (their index in the range) along the path
// (x0 + dx t, y0 + dy t); eta: the conservative walk's margin (0 otherwise).
template <int W, Addressing ADDRESSING>
void queue_walk(const KernelContext<W, ADDRESSING>& k, vfloat<W> x0, vfloat<W> y0, vfloat<W> dx, vfloat<W> dy,
                vfloat<W> eta, WalkQueue& q, int i) {
  using F = vfloat<W>;
  using I = vint<W>;
  const int top = k.texture.min_depth_pyramid.levels - 1;  // -1: no interior cell (CLAMP, one texel wide)
  const auto put = [&](WalkQueue::Float field, F value) { value.store(q.f[field] + i); };
  const auto put_int = [&](WalkQueue::Int field, I value) { value.store(q.i[field] + i); };
  // One axis, mirrored where the path runs towards -x (never dx = -0: the callers compute 0 - p;
  // dx = +0 leaves on the high side at infinity). Negation is a product by -1 (exact, signed zeros
  // included); the cell of x0 is floor(x0) on the path towards +x and the cell left of a side on
  // the path towards -x, ~floor(-x0) either way.
  const auto axis = [&](F x, F d, int n, WalkQueue::Float xf, WalkQueue::Float df, WalkQueue::Float inv_f,
                        WalkQueue::Int flip_f, WalkQueue::Int low_f, WalkQueue::Int high_f,
                        WalkQueue::Int cell_f) {
    const vbool<W> mirrored = d < F(0.0f);
    const I flip = select(mirrored, I(-1), I(0));
    const F sign = select(mirrored, F(-1.0f), F(1.0f));
    put(xf, x * sign);
    put(df, d * sign);
    put(inv_f, F(1.0f) / d * sign);
    put_int(flip_f, flip);
    I cell = to_int(floor(x * sign));
    if constexpr (ADDRESSING == Addressing::clamp) {
      // The interior cells 0 .. n - 2, mirrored [~(n - 2), ~0]; the edge cells beyond them.
      const I low = select(mirrored, I(n - 2), I(0)) ^ flip, high = select(mirrored, I(0), I(n - 2)) ^ flip;
      put_int(low_f, low);
      put_int(high_f, high);
      cell = min(max(cell, low - I(1)), high + I(1));
    }
    put_int(cell_f, cell);
  };
  axis(x0, dx, k.texture.width, WalkQueue::x0, WalkQueue::dx, WalkQueue::inv_dx, WalkQueue::flip_x,
       WalkQueue::low_x, WalkQueue::high_x, WalkQueue::cell_x);
  axis(y0, dy, k.texture.height, WalkQueue::y0, WalkQueue::dy, WalkQueue::inv_dy, WalkQueue::flip_y,
       WalkQueue::low_y, WalkQueue::high_y, WalkQueue::cell_y);
  put(WalkQueue::eta, eta);
  // Start where a block is about an eighth of the path's extent: the levels above it would
  // almost always be descended again, those below it climbed.
  const F extent = abs(dx) + abs(dy);
  I level(0);
  for (int l = 1; l <= top; ++l) level = select(extent >= F(float(1 << (l + 3))), I(l), level);
  put_int(WalkQueue::level, level);
  // Each pass advances t or descends a level: the cells on the path times the levels bound it.
  put_int(WalkQueue::bound,
          to_int(floor(min(F(float(2 * (top + 2))) * (extent + F(2.0f)), F(kMaxLanePasses)))));
}

// The pyramid walk of maximum-mipmap tracing over a queue of rays. CONSERVATIVE (the exact
// reference's float pass): every test is loosened by the margin eta, which bounds the walk's
// rounding, so that a lane stops no later than the first cell the exact path touches
// (docs/conventions.md, the exact intersection). EVENT_LANES: how many lanes wait before the
// packet's cells are solved and its free lanes refilled.
template <bool CONSERVATIVE, int W, Addressing ADDRESSING, int EVENT_LANES>
class PyramidWalker {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;
  static constexpr bool kRepeat = ADDRESSING != Addressing::clamp;
  static_assert(EVENT_LANES >= 1 && EVENT_LANES <= W, "a walk's event lanes are some of its lanes");

  explicit PyramidWalker(KernelContext<W, ADDRESSING>& k)
      : k_(k),
        texture_(k.texture),
        pyramid_(k.texture.min_depth_pyramid.texels),
        top_(k.texture.min_depth_pyramid.levels - 1),
        top_level_(top_ < 0 ? 0 : top_),
        width_log2_(std::countr_zero(unsigned(k.texture.width))),
        width_(float(k.texture.width)),
        height_(float(k.texture.height)),
        inv_width_(1.0f / float(k.texture.width)),
        inv_height_(1.0f / float(k.texture.height)),
        pow2_offsets_(std::int32_t(std::int64_t(k.texture.width) * k.texture.height * 4 / 3)) {
    // Per level: where its entries start (MinDepthPyramid's layout) and its blocks a side
    // (ceil(cells / 2^L)), looked up by each lane's level (register permutes where the ISA has
    // them).
    static_assert(MinDepthPyramid::kMaxLevels <= 16, "the per-level tables are Table16s");
    const int last_cell_x = kRepeat ? texture_.width - 1 : texture_.width - 2;
    for (int l = 0; l <= top_level_; ++l) {
      level_offset_.values[l] = top_ < 0 ? 0 : texture_.min_depth_pyramid.level_offsets[l];
      level_blocks_x_.values[l] = (last_cell_x >> l) + 1;
    }
  }

  // Walks the queued rays [0, n) of q to their ends, leaving each ray's outcome at its position.
  void run(WalkQueue& q, int n, WalkOutcomes& out) {
    q.end_at(n);
    n_ = n;
    State s;
    s.t = F(0.0f);
    s.cx = s.cy = s.level = s.reads = I(0);
    int next = 0;
    take(q, next, B::all_true(), s);
    Pass last;
    last.skip = last.stay = B::all_true();  // no lane waits
    // Each step ends a ray or solves a cell, and each ray takes at most its bound of passes and as
    // many solves.
    const std::int64_t max_steps = std::int64_t(n + W) * (2 * std::int64_t(kMaxLanePasses) + 2);
    for (std::int64_t step = 0; step < max_steps; ++step) {
      if (!events(q, next, last, s, out)) return;
      // Passes until EVENT_LANES lanes wait (or, once the queue is empty, every live lane), or a
      // lane reaches its bound.
      const int dead = W - std::popcount(mask_bits(live()));
      const int most_staying = W - std::min(W, dead + EVENT_LANES);
      const std::uint32_t budget = passes_left(s);
      std::uint32_t done = 0;
      while (done < budget) {
        last = pass(s);
        ++done;
        if (std::popcount(mask_bits(last.stay)) <= most_staying) break;
      }
      if (!CONSERVATIVE && (kRepeat || top_ >= 0))
        k_.count_packet_reads(int(done));  // an entry a lane a pass
    }
  }

 private:
  // A lane's walk: where it is (t, its cell, mirrored, and its level) and minus the pyramid
  // entries it has read.
  struct State {
    F t;
    I cx, cy, level, reads;
  };

  // The lanes' rays' constants (the queue's fields), the samples of their solves, and their queue
  // positions.
  struct Slots {
    alignas(64) float f[WalkQueue::kFloats][W];
    alignas(64) std::int32_t i[WalkQueue::kConstantInts][W];
    alignas(64) std::int32_t extra[W], ray[W];
  };

  F slot(WalkQueue::Float field) const { return F::load(slots_.f[field]); }
  I slot(WalkQueue::Int field) const { return I::load(slots_.i[field]); }
  // Lanes that hold a ray.
  B live() const { return I::load(slots_.ray) < I(n_); }

  // The box a lane is in, mirrored: its block at its level (blocks tile the period: REPEAT keeps
  // a level only while 2^L divides both sides), or (CLAMP edge cells) the cell, infinite on its
  // outer side; where the path leaves it (tx, ty, te), where the lane's span ends (t_end).
  struct Box {
    B interior;
    I lo_x, lo_y;      // its first cells
    I last_x, last_y;  // its last cells
    I hi_x, hi_y;      // the cells past it, where the path leaves it
    F tx, ty, te, t_end;
  };

  Box box(const State& s) const {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    Box b;
    const I block = I(-1) << s.level;  // the bits of a block's first cell
    b.lo_x = s.cx & block;
    b.lo_y = s.cy & block;
    b.hi_x = b.lo_x - block;
    b.hi_y = b.lo_y - block;
    b.last_x = b.hi_x - I(1);
    b.last_y = b.hi_y - I(1);
    F hi_x, hi_y;  // as floats
    if constexpr (kRepeat) {
      b.interior = B::all_true();
    } else {
      const I low_x = slot(WalkQueue::low_x), high_x = slot(WalkQueue::high_x);
      const I low_y = slot(WalkQueue::low_y), high_y = slot(WalkQueue::high_y);
      const B below_x = s.cx < low_x, above_x = high_x < s.cx, below_y = s.cy < low_y,
              above_y = high_y < s.cy;
      b.interior = !(below_x | above_x | below_y | above_y);
      b.lo_x = select(b.interior, max(b.lo_x, low_x), select(below_x, I(INT32_MIN), s.cx));
      b.lo_y = select(b.interior, max(b.lo_y, low_y), select(below_y, I(INT32_MIN), s.cy));
      b.last_x = select(b.interior, min(b.last_x, high_x), s.cx);
      b.last_y = select(b.interior, min(b.last_y, high_y), s.cy);
      b.hi_x = b.last_x + I(1);
      b.hi_y = b.last_y + I(1);
      hi_x = select(above_x, F(kInf), to_float(b.hi_x));
      hi_y = select(above_y, F(kInf), to_float(b.hi_y));
    }
    if constexpr (kRepeat) {
      hi_x = to_float(b.hi_x);
      hi_y = to_float(b.hi_y);
    }
    b.tx = (hi_x - slot(WalkQueue::x0)) * slot(WalkQueue::inv_dx);
    b.ty = (hi_y - slot(WalkQueue::y0)) * slot(WalkQueue::inv_dy);
    b.te = min(b.tx, b.ty);
    b.t_end = min(b.te, F(1.0f));
    return b;
  }

  // The cell a coordinate lies in, clamped into the box (rounding may put it just outside).
  static I cell_in(F x, I lo, I last) { return min(max(to_int(floor(x)), lo), last); }

  // The lanes `move` leave the box (without a hit) into the next; the lanes `descend` go down a
  // level, into the cell where the path reaches the block's shallowest depth, clear_above, if
  // that is past t.
  void advance(State& s, const Box& b, B move, B descend, F clear_above) const {
    const B reach = descend & (clear_above > s.t);
    const F t_next = select(move, b.te, min(clear_above, b.t_end));
    const I at_x = cell_in(slot(WalkQueue::x0) + slot(WalkQueue::dx) * t_next, b.lo_x, b.last_x);
    const I at_y = cell_in(slot(WalkQueue::y0) + slot(WalkQueue::dy) * t_next, b.lo_y, b.last_y);
    const B exit_x = and_not(move, b.tx > b.ty), exit_y = and_not(move, b.ty > b.tx);
    // Up a level only out of the block's parent: inside it the parent would be descended again.
    // The parent changes where the crossed side is a multiple of twice the block's side: for a
    // whole block, where the block is odd.
    I parent;
    if constexpr (kRepeat) {
      parent = ((to_int(exit_x) & s.cx) | (to_int(exit_y) & s.cy)) >> s.level;
    } else {                                       // CLAMP's sides may be the map's
      const I twice = (I(-2) << s.level) ^ I(-1);  // the bits below 2^(L + 1)
      parent = (to_int(exit_x) & to_int((b.hi_x & twice) == I(0))) |
               (to_int(exit_y) & to_int((b.hi_y & twice) == I(0)));
    }
    const B step = move | reach;
    I cx = select(exit_x, b.hi_x, at_x), cy = select(exit_y, b.hi_y, at_y);
    if constexpr (!kRepeat) {  // the edge cells at most
      cx = min(max(cx, slot(WalkQueue::low_x) - I(1)), slot(WalkQueue::high_x) + I(1));
      cy = min(max(cy, slot(WalkQueue::low_y) - I(1)), slot(WalkQueue::high_y) + I(1));
    }
    s.t = select(step, t_next, s.t);
    s.cx = select(step, cx, s.cx);
    s.cy = select(step, cy, s.cy);
    s.level = s.level + (parent & I(1) & to_int(s.level < I(top_level_))) + to_int(descend);
  }

  // One pass: the box each lane is in, the pyramid entry of its block read, and what the lane
  // does next: skip the box (moving on, or beyond depth 1: its ray has returned), descend a
  // level, or wait for its cell to be solved. A lane that stays (moves or descends) has read its
  // entry; one whose ray has returned or that waits passes without effect (its pass finds the
  // same), and so does a lane without a ray (it waits at level 0).
  struct Pass {
    B skip, stay;
  };

  Pass pass(State& s) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const Box b = box(s);
    F clear_above(-kInf);
    if (kRepeat || top_ >= 0) {
      // The block's entry, at its unmirrored index; REPEAT wraps it into the level's blocks.
      const I ox = s.cx ^ slot(WalkQueue::flip_x), oy = s.cy ^ slot(WalkQueue::flip_y);
      I entry;
      if constexpr (ADDRESSING == Addressing::repeat_pow2) {
        // Row (oy mod H) >> L of the level's W >> L blocks, column (ox mod W) >> L: shifted
        // together, as a row of W (2^L divides W).
        // Level L starts at sum_{k<L} A / 4^k = K - (K >> 2L) entries, K = floor(4A / 3) for
        // A = W H a power of two (the floors agree: 4A and 4A >> 2L have the same parity of log2).
        const I row = ((oy & I(texture_.height - 1)) >> s.level) << width_log2_;
        entry = (I(pow2_offsets_) - (I(pow2_offsets_) >> (s.level + s.level))) +
                ((row + (ox & I(texture_.width - 1))) >> s.level);
      } else {
        I wx = ox >> s.level, wy = oy >> s.level;
        if constexpr (ADDRESSING == Addressing::repeat) {
          const F size = pow2(s.level), inv_size = pow2(I(0) - s.level);
          wx = to_int(wrap_cell(to_float(wx), width_ * inv_size, inv_width_ * size));
          wy = to_int(wrap_cell(to_float(wy), height_ * inv_size, inv_height_ * size));
        }
        entry = lookup(level_offset_, s.level) + wy * lookup(level_blocks_x_, s.level) + wx;
      }
      if constexpr (kRepeat) {
        clear_above = gather(pyramid_, entry);
      } else {
        clear_above = select(b.interior, gather(pyramid_, select(b.interior, entry, I(0))), F(-kInf));
      }
    }
    if constexpr (CONSERVATIVE) clear_above = clear_above - slot(WalkQueue::eta);
    Pass p;
    p.skip = b.t_end < clear_above;  // (never where no entry was read: -infinity)
    B descend = and_not(I(0) < s.level, p.skip);
    if constexpr (!kRepeat) descend = descend & b.interior;
    const B move = p.skip & (b.te < F(1.0f));
    p.stay = move | descend;
    advance(s, b, move, descend, clear_above);
    s.reads = s.reads + to_int(p.stay);
    return p;
  }

  // The cell test of the lanes `solving`: whether the path meets the patch of its cell before it
  // leaves the box. Where it does, `cell` holds the quadratic over the span, or (CONSERVATIVE:
  // the exact reference solves the cell again in double) the texels; 0 elsewhere.
  B test_cell(const State& s, const Box& b, B solving, F (&cell)[4]) {
    F t00, t10, t01, t11;
    const I flip_x = slot(WalkQueue::flip_x), flip_y = slot(WalkQueue::flip_y);
    const I cx = s.cx ^ flip_x, cy = s.cy ^ flip_y;  // unmirrored
    cell_texels<ADDRESSING>(texture_, cx, cy, t00, t10, t01, t11);
    k_.count_packet_reads(CONSERVATIVE ? 1 : 4);
    // The samples of the solve: four texels (one cell tested, for the conservative walk); a cell
    // tested where the pass read no pyramid entry (CLAMP's edge cells) less that read.
    const I extra =
        I::load(slots_.extra) +
        select(solving, select(b.interior, I(CONSERVATIVE ? 1 : 4), I(CONSERVATIVE ? 1 : 3)), I(0));
    extra.store(slots_.extra);
    // The unmirrored path, as the patch is unmirrored.
    const F sign_x = select(flip_x == I(0), F(1.0f), F(-1.0f)),
            sign_y = select(flip_y == I(0), F(1.0f), F(-1.0f));
    const F x0 = slot(WalkQueue::x0) * sign_x, y0 = slot(WalkQueue::y0) * sign_y;
    const F dx = slot(WalkQueue::dx) * sign_x, dy = slot(WalkQueue::dy) * sign_y;
    const F eta = CONSERVATIVE ? slot(WalkQueue::eta) : F(0.0f);
    const F fx = (x0 - to_float(cx)) + dx * s.t, fy = (y0 - to_float(cy)) + dy * s.t;
    const F e = t10 - t00, f = t01 - t00, g = (t11 - t10) - (t01 - t00);
    const F c0 = s.t - (t00 + e * fx + f * fy + g * fx * fy) + eta;
    const F c1 = F(1.0f) - (e * dx + f * dy + g * (fx * dy + fy * dx));
    const F c2 = F(0.0f) - g * dx * dy;
    const F span = b.t_end - s.t;
    const B hit = solving & reaches_patch(c0, c1, c2, span);
    const F zero(0.0f);
    cell[0] = select(hit, CONSERVATIVE ? t00 : c0, zero);
    cell[1] = select(hit, CONSERVATIVE ? t10 : c1, zero);
    cell[2] = select(hit, CONSERVATIVE ? t01 : c2, zero);
    cell[3] = select(hit, CONSERVATIVE ? t11 : span, zero);
    return hit;
  }

  // The most passes every live lane can take within its bound (at least one: the events ended the
  // lanes at their bounds).
  std::uint32_t passes_left(const State& s) const {
    const I left =
        select(live(), slot(WalkQueue::bound) + s.reads, I(std::numeric_limits<std::int32_t>::max()));
    return std::uint32_t(std::max(reduce_min(left), 1));
  }

  // The free lanes take the queue's rays from `next` on, in lane order; past its last ray, none.
  void take(const WalkQueue& q, int& next, B free, State& s) {
    for (int c = 0; c < WalkQueue::kFloats; ++c)
      if (CONSERVATIVE || c != WalkQueue::eta)
        expand_load(q.f[c] + next, free, F::load(slots_.f[c])).store(slots_.f[c]);
    for (int c = 0; c < WalkQueue::kConstantInts; ++c)
      if (!kRepeat || c == WalkQueue::flip_x || c == WalkQueue::flip_y || c == WalkQueue::bound)
        expand_load(q.i[c] + next, free, I::load(slots_.i[c])).store(slots_.i[c]);
    expand_load(kWalkQueuePositions.values + next, free, I::load(slots_.ray)).store(slots_.ray);
    select(free, I(0), I::load(slots_.extra)).store(slots_.extra);
    s.t = select(free, F(0.0f), s.t);
    s.cx = expand_load(q.i[WalkQueue::cell_x] + next, free, s.cx);
    s.cy = expand_load(q.i[WalkQueue::cell_y] + next, free, s.cy);
    s.level = expand_load(q.i[WalkQueue::level] + next, free, s.level);
    s.reads = select(free, I(0), s.reads);
    // Lanes past the last ray read the padding (whole packets of it), and stay there.
    next = std::min(next + std::popcount(mask_bits(free)), n_);
  }

  // The events of the last pass (`last`: the lanes that did not stay wait for a solve or, having
  // skipped, have returned): the waiting cells solved, the lanes at their bounds cut off, the
  // ended rays' outcomes left, and their lanes refilled. Returns whether any lane holds a ray.
  bool events(const WalkQueue& q, int& next, const Pass& last, State& s, WalkOutcomes& out) {
    const B live_lanes = live();
    const B waited = and_not(live_lanes, last.stay);
    const B solving = and_not(waited, last.skip), returned = waited & last.skip;
    // The pass that found a lane's event read its entry.
    s.reads = s.reads + to_int(waited);
    F cell[4] = {F(0.0f), F(0.0f), F(0.0f), F(0.0f)};
    B hit = !B::all_true(), cleared = !B::all_true();
    if (any(solving)) {
      // A lane solves at level 0, or in a CLAMP edge cell: either way its box is its cell.
      State cell_state = s;
      cell_state.level = I(0);
      const Box b = box(cell_state);
      hit = test_cell(s, b, solving, cell);
      const B miss = and_not(solving, hit), before_1 = b.te < F(1.0f);
      cleared = and_not(miss, before_1);
      advance(s, b, miss & before_1, !B::all_true(), F(0.0f));
    }
    // Past its bound a lane stops where it is, its path clear down to t (cut off).
    const B over = and_not(live_lanes, returned | hit | cleared) & !(I(0) < slot(WalkQueue::bound) + s.reads);
    const B ended = returned | hit | cleared | over;
    if (none(ended)) return any(live_lanes);
    leave_outcomes(s, ended, hit, over, cell, out);
    take(q, next, ended, s);
    return any(live());
  }

  // The outcomes of the lanes `ending` at their rays' positions.
  void leave_outcomes(const State& s, B ending, B hit, B over, const F (&cell)[4], WalkOutcomes& out) const {
    alignas(64) float t[W], cx[W], cy[W], end[W], c[4][W];
    alignas(64) std::int32_t samples[W];
    s.t.store(t);
    if constexpr (CONSERVATIVE) {  // maxmip's hit needs no cell
      to_float(s.cx ^ slot(WalkQueue::flip_x)).store(cx);
      to_float(s.cy ^ slot(WalkQueue::flip_y)).store(cy);
    }
    select(hit, F(float(WalkEnd::reached)),
           select(over, F(float(WalkEnd::cut_off)), F(float(WalkEnd::clear))))
        .store(end);
    for (int k = 0; k < 4; ++k) cell[k].store(c[k]);
    (I::load(slots_.extra) - (CONSERVATIVE ? I(0) : s.reads)).store(samples);
    for (std::uint32_t bits = mask_bits(ending); bits != 0; bits &= bits - 1) {
      const int lane = std::countr_zero(bits);
      const int r = slots_.ray[lane];
      out.t[r] = t[lane];
      if constexpr (CONSERVATIVE) {
        out.cx[r] = cx[lane];
        out.cy[r] = cy[lane];
      }
      out.end[r] = end[lane];
      for (int k = 0; k < 4; ++k) out.cell[k][r] = c[k][lane];
      out.samples[r] = samples[lane];
    }
  }

  KernelContext<W, ADDRESSING>& k_;
  const KernelTexture& texture_;
  const float* pyramid_;
  const int top_;  // -1: no interior cell (CLAMP, one texel wide)
  const int top_level_;
  const int width_log2_;  // REPEAT of a power-of-two side
  const F width_, height_, inv_width_, inv_height_;
  const std::int32_t pow2_offsets_;  // K (REPEAT of power-of-two sides)
  Table16<std::int32_t> level_offset_, level_blocks_x_;
  Slots slots_{};
  int n_ = 0;  // the rays queued
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
