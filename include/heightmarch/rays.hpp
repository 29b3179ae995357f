#pragma once
// Rays in tangent space (docs/conventions.md) and the views that make them, as structure-of-arrays
// tile batches: the view is cut into tiles, each tile's rays are stored together, ordered in
// blocks of 8 x 2 pixels (kBlockWidth x kBlockHeight).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace heightmarch {

// Every tile's ray range starts at a multiple of this and is padded to it, so packet kernels
// of any width (up to two AVX-512 packets) never need a partial load.
inline constexpr std::size_t kRayAlignment = 32;
inline constexpr std::uint32_t kPaddingRay = 0xffffffffu;

// A view's pixel blocks: a packet of 4 or 8 consecutive rays is part of one pixel row, 16 are
// two rows. Wide rather than square because a row of pixels stays within one or two texel rows
// at every layer step, where a column of four spans up to five (the views look along v, which
// they foreshorten): the kernels then read a packet's taps from a small window of the depth map
// instead of gathering them. Measured on the default view at 32 layers: 97-99.6% of 8-ray packets
// have their taps in two texel rows of 8 columns (48-60% with 4 x 4 blocks), 97-99.4% of 16-ray
// packets in AVX-512's window of 8 x 5 texels (83-89% with 4 x 4 blocks).
inline constexpr int kBlockWidth = 8;
inline constexpr int kBlockHeight = 2;
// A view set around the surface turns each cell of kViewCell x kViewCell pixels to its own azimuth
// (views.cpp): whole blocks, so no packet spans two azimuths.
inline constexpr int kViewCell = 8;

struct RayBatch {
  // T (entry point on the top plane) and V (unit, towards the eye, vz > 0).
  std::vector<float> tx, ty, vx, vy, vz;
  // The pixel footprint: how T changes to the next pixel in x and in y (trilinear filtering's
  // gradients, textureGrad's dPdx and dPdy), from the view's pixel grid (pixel_gradients()); 0
  // for rays without a grid (a rays file), which then read level 0.
  std::vector<float> du_dx, dv_dx, du_dy, dv_dy;
  // For each ray, its pixel (y * image_width + x) or input row; kPaddingRay for padding.
  std::vector<std::uint32_t> origin;
  // Tile t holds rays [tile_offsets[t], tile_offsets[t + 1]).
  std::vector<std::size_t> tile_offsets{0};
  // For each ray, the view of its set it belongs to, from 0 (views.cpp): the rays that share one
  // draw of azimuth and offset, or (a single view, a list of rays) a tile; numbered so that views
  // 2k and 2k + 1 are neighbours in azimuth and angle (metrics.cpp pairs them).
  std::vector<std::uint32_t> view;
  std::uint32_t views = 0;
  int image_width = 0;  // pixels of the view (rays file: row count x 1)
  int image_height = 0;
  std::size_t ray_count = 0;  // rays without the padding

  std::size_t size() const { return tx.size(); }
  std::size_t tile_count() const { return tile_offsets.size() - 1; }
  bool is_padding(std::size_t i) const { return origin[i] == kPaddingRay; }
};

// The default view's span of view angles, degrees from the normal.
inline constexpr float kDefaultNearDegrees = 30.0f, kDefaultFarDegrees = 80.0f;
inline constexpr float kMaxViewDegrees = 89.0f;

// Where a batch's rays come from: the perspective benchmark view, a sweep of one V over a grid
// of T, a CSV file of rays (width x height is then rows x 1, known once loaded), or a view set
// (docs/measures.md#view-sets): the perspective view or a sweep seen around the surface (each
// tile of its frame from its own azimuth), LearnOpenGL's rotating quad at `views` frames of one
// turn, or a user's camera poses (frames and poses side by side in the batch's image). A tile
// never spans two views.
struct ViewSpec {
  enum class Kind { perspective, sweep, rays_file, tutorial, poses };
  Kind kind = Kind::perspective;
  int width = 1024;  // of the frame; the tutorial: of each of its frames
  int height = 1024;
  float theta_degrees = 0.0f;  // sweep: angle of V from the normal
  // perspective: the view angle from the normal at the near edge of the plane (v = 0) and at the
  // far edge (v = 1), on the centre line: the span of angles a scene shows the surface at
  float near_degrees = kDefaultNearDegrees, far_degrees = kDefaultFarDegrees;
  float phi_degrees = 270.0f;  // sweep: azimuth of V (270: eye towards -v, as the default view)
  // perspective and sweep: seen around the surface, every tile of the frame from an azimuth and
  // at an offset of its own (views.cpp); else the single view
  bool around = false;
  int views = 1;  // tutorial: the frames of one turn
  // What a set draws (each view's azimuth within its sector, its uv offset on the repeating map,
  // the tutorial's phase of the turn): 0 draws nothing; a held-out set is its selection set at
  // seed + 1 (held_out_view).
  std::uint32_t seed = 0;
  // Not the window's rays but this many fresh ones: every azimuth and position uniform, the view
  // angles drawn from the window's own (the outside check's rays).
  std::size_t fresh_rays = 0;
  std::string path;    // rays_file: the rays CSV; poses: the camera poses CSV
  int tile_size = 32;  // tile side in pixels (rays_file: tile_size^2 rays per tile)
  friend bool operator==(const ViewSpec&, const ViewSpec&) = default;
};

inline constexpr int kMaxViewSide = 16384;

// What a run holds per ray of its batch, for the memory budget: the ray (T, V, origin, view, gradients),
// its hits, the exact and reference hits, the error and, with --out, the images' pixels
// (measured: a 4096 x 4096 --out trace peaks at about 139 bytes a ray before the gradients' 16).
inline constexpr double kBytesPerRay = 176.0;
// And per row of a rays file: its columns as read (its row of rays.csv is written back through a
// 1 MiB buffer: a 2,000,000-ray file with --out peaks at 331 MB, against 746 MB estimated).
inline constexpr double kBytesPerRayCsvRow = 180.0;

// Rays a batch holds per ray given, padding included: a tile's rays are padded to a multiple of
// kRayAlignment, so --tile 1 holds 32 per ray.
inline double padding_factor(int tile_size) {
  const double per_tile = double(tile_size) * double(tile_size);
  return std::ceil(per_tile / double(kRayAlignment)) * double(kRayAlignment) / per_tile;
}
inline constexpr int kDefaultTileSize = 32;

// "default", "default:NEAR-FAR" (the perspective view's span of angles) or "sweep:THETA[,PHI]"
// (degrees); throws InputError.
ViewSpec parse_view(const std::string& text, int width, int height);
// "NEAR-FAR" in degrees, 0 <= NEAR < FAR <= kMaxViewDegrees, into the view; throws InputError.
void parse_view_angles(const std::string& text, ViewSpec& view);
ViewSpec sweep_view(double theta_degrees, int width, int height);  // at the default azimuth
ViewSpec rays_file_view(const std::string& path);

// The windows `--views` names (docs/measures.md#view-sets), each with its selection seed: the
// single default view (today's, seed 0), the set around the surface (seed 1), the tutorial's
// scene (kTutorialFrames frames, seed 0: its own frames) and a CSV of camera poses (seed 0: as
// given).
inline constexpr int kTutorialFrames = 16;
inline constexpr int kTutorialWidth = 800, kTutorialHeight = 600;  // the tutorial's window
inline constexpr int kMaxSetViews = 4096;
// "single", "around", "tutorial[:N]" or a camera-pose CSV file, applied to a perspective view
// (its span and size kept) or a sweep ("single" and "around" only): sets its kind, around, views
// and selection seed. Throws InputError.
void apply_views(const std::string& text, ViewSpec& view);
// The held-out set of a window: the same window drawn at seed + 1 (other azimuths within their
// sectors in another order, other offsets, another phase of the tutorial's turn).
ViewSpec held_out_view(const ViewSpec& view);
// More than one view, or fresh rays: a figure over it is another series than a single view's.
bool is_view_set(const ViewSpec& view);
// Sizes a window so that it holds about `rays` rays: a square frame; the tutorial's frames at 4:3,
// scaled by the share of their pixels that see the quad's front over the turn. A pose file keeps
// its poses' sizes.
void size_views_for_rays(ViewSpec& view, double rays);

// "default 1024x1024", "default:45-85 1024x1024" (angles other than 30-80), "sweep:70,270 128x128",
// "rays:FILE"; sets: "around 1024x1024", "around:45-85 1024x1024", "sweep:70 around 128x128",
// "tutorial:16 800x600", "poses:FILE", then " seed N" where
// the seed is not the window's selection seed, and "fresh 100000 rays like ..." for fresh rays
std::string describe(const ViewSpec& view);

// The default view: a perspective camera looking at the plane so view angles span near_degrees
// (near edge) to far_degrees (far edge); at 30 and 80, from (0.5, -0.113, 0.196). The sweep view: one fixed V
// over a width x height grid of T at pixel centres of [0,1]^2. A rays_file view loads its CSV
// (load_rays_csv).
RayBatch make_view_rays(const ViewSpec& view);

// Sets the batch's gradients from its pixel grid (origin = y * image_width + x), as a GPU's quad
// derivatives (dFdxFine, dFdyFine) take them: the difference of T to the pixel's partner in its
// 2 x 2 quad (x ^ 1, y ^ 1), or where no ray of the batch is there (the partner misses the plane),
// to its neighbour on the other side; 0 along an axis with neither. Padding copies its tile's
// last ray. For views; a batch without a grid keeps zero gradients. The image holds frames of
// frame_width x frame_height side by side (a view set's: views.cpp), and no gradient crosses
// from one frame into another.
void set_pixel_gradients(RayBatch& rays, int frame_width, int frame_height);

// A CSV file with header tx,ty,vx,vy,vz; rays keep their input order, cut into tiles of
// tile_size^2 rays. V is normalised; vz <= 0, NaN and malformed rows are InputErrors.
RayBatch load_rays_csv(const std::string& path, int tile_size = kDefaultTileSize);

// The one check of a batch handed over whole (a GLSL worker's message): the nine arrays of one
// length, T finite within 1e6, V finite with V.z > 0, gradients finite within 1e6. Throws
// InputError naming the first bad ray.
void check_rays(const RayBatch& rays);

// Builds a batch from explicit rays (used by the CSV loader and tests).
RayBatch make_ray_list(const std::vector<float>& tx, const std::vector<float>& ty,
                       const std::vector<float>& vx, const std::vector<float>& vy,
                       const std::vector<float>& vz, int tile_size = kDefaultTileSize);

}  // namespace heightmarch
