#pragma once
// The relaxed cone map of the cone technique (docs/techniques.md#cone): per texel p, a cone with
// its apex on the surface at p's centre (depth D_p) opening upward, stored as its ratio c(p), the
// cone's radius in uv per unit of depth above the apex.
//
// The relaxed cone (Policarpo and Oliveira, GPU Gems 3 ch. 18) may hold surface, but no point
// where a ray that starts at the top of p's axis (depth 0, above p) and goes down leaves the
// surface (passes from below the bilinear surface of docs/conventions.md to above it), so such
// a ray crosses the surface at most once inside the cone. A ray from the axis top leaves the
// surface at E only where the surface falls away from p faster than the ray falls,
// slope(E) > depth(E) / dist(p, E), and E narrows the cone only if depth(E) < D_p.
//
// The map stores a lower bound of that cone, found piece by piece: each texel cell (the
// bilinear patch between four texel centres) is cut into kConeCellSplit^2 sub-patches P, each
// bilinear, with its shallowest depth m_P, a bound S_P(p) of its slope along the directions from
// p into it (the support of its gradient's box over that arc) and a bound G_P of |grad D|. An
// exit in P lies at least m_P / S_P from p, so
//   c(p) = min(kMaxConeRatio, min over P with m_P < D_p, S_P > 0 and
//          m_P < S_P maxdist(p, P) of  max(dist(p, P), m_P / S_P) / (D_p - m_P)),
// and a P touching p bounds it by at least 1 / G_P (the depth climbs at most G_P per uv from p).
// Distances are in uv; REPEAT counts every image of the periodic surface, CLAMP the edge strips
// the clamp extends to infinity as cells (their slopes bounded per axis).
//
// Built in parallel (TBB) over batches of 4 x 4 texels. A batch walks a pyramid of 2 x 2 blocks
// of cells depth first, keeping per block and per side of an apex the least m and m / S (S per
// axis) and the box of the gradient: a block is opened for the texels whose best cone so far it
// may narrow (its lower bound of the term above, with the support of its gradient box over the
// arc from the apex), starting from the cells that bounded the batch before it. The result is
// exactly the least term (tests/cone_map_test.cpp checks it against every cell).
#include <memory>
#include <vector>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/sampler.hpp"

namespace heightmarch {

// Cones wider than this are stored as this: a step then covers c / (r + c) of the ray's height
// above the surface (r: the ray's uv per unit depth, s tan(theta)), 87% at s = 0.1 and 80 degrees.
// It also bounds the search: REPEAT images up to kMaxConeRatio tiles away.
inline constexpr float kMaxConeRatio = 4.0f;

// Sub-patches per cell side: finer pieces separate a cell's shallow corner from its steep part.
inline constexpr int kConeCellSplit = 2;

struct ConeMap {
  int width = 0, height = 0;
  Wrap wrap = Wrap::repeat;
  std::vector<float> depth;  // the depth map's texels, row-major (the texture's first channel)
  std::vector<float> ratio;  // c(p), row-major (its second channel)
  SamplerTexture texture;    // the ratios in the packet sampler's layout
  double build_seconds = 0;  // wall time of the build, at the TBB parallelism it ran with

  // As the packet kernels read it: the ratios in the sampler's layout. As the GLSL does: (depth,
  // ratio) interleaved in an RG32F texture with GL_LINEAR and the run's wrap, so one read gives
  // both, as one CPU sample does.
  TextureSlot slot() const { return {texture.texels.data()}; }
  GlImage gl_image() const;
};

// Builds the cone map (TBB over rows).
ConeMap build_cone_map(const DepthMap& map, Wrap wrap);

// The bound one cell puts on texel (i, j)'s cone, the term of the definition above (infinite if
// none): cell (cell_x, cell_y) has corners at texel centres (cell_x, cell_y) to (cell_x + 1,
// cell_y + 1); REPEAT takes any integers (images), CLAMP -1 to W - 1 (and H - 1), the first and
// last standing for the strips beyond the edges. c(p) is the least of these and kMaxConeRatio.
double cone_cell_bound(const DepthMap& map, Wrap wrap, int i, int j, int cell_x, int cell_y);

// The cone map of this depth map (by content) and wrap mode, built on the first call and kept
// for the life of the process. Thread-safe.
std::shared_ptr<const ConeMap> cached_cone_map(const DepthMap& map, Wrap wrap);

}  // namespace heightmarch
