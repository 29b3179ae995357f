#pragma once
// Rays in tangent space (docs/conventions.md) as structure-of-arrays tile batches: a view
// (views.hpp) is cut into tiles, each tile's rays are stored together, ordered in blocks of 8 x 2
// pixels (kBlockWidth x kBlockHeight); a list of rays (a rays file) is cut into tiles in its order.
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
  // For each ray, the view of its set it belongs to, from 0 (views.hpp): the rays that share one
  // draw of azimuth and offset, or (a single view, a list of rays) a tile; numbered so that views
  // 2k and 2k + 1 are neighbours in azimuth and angle (metrics.cpp pairs them).
  std::vector<std::uint32_t> view;
  std::uint32_t views = 0;
  int image_width = 0;  // pixels of the view (rays file: row count x 1)
  int image_height = 0;
  // The frames the image holds side by side, each its own pixel grid (set_pixel_gradients): a
  // view set's frames, or the whole image; 0 for rays without a grid (a rays file).
  int frame_width = 0, frame_height = 0;
  std::size_t ray_count = 0;  // rays without the padding

  std::size_t size() const { return tx.size(); }
  std::size_t tile_count() const { return tile_offsets.size() - 1; }
  bool is_padding(std::size_t i) const { return origin[i] == kPaddingRay; }
};

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
// The largest side of a view's (or a camera pose's) image, in pixels.
inline constexpr int kMaxViewSide = 16384;

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

// The one check of every ray batch, whatever made it (a view, a view set, the tutorial's scene, a
// user's camera poses, a rays file, fresh rays: make_view_rays(); a GLSL worker's message): what
// no kernel can take, for ray i (padding included), or "" for a fit ray: T finite within 1e6, V
// finite with V.z > 0, the pixel footprint's gradients finite within 1e6. Its arrays must be of
// one length (check_rays).
std::string ray_fault(const RayBatch& rays, std::size_t i);
// Throws InputError "ray N of the batch: FAULT" for the first ray with a fault, or for arrays of
// different lengths.
void check_rays(const RayBatch& rays);

// Builds a batch from explicit rays (used by the CSV loader and tests).
RayBatch make_ray_list(const std::vector<float>& tx, const std::vector<float>& ty,
                       const std::vector<float>& vx, const std::vector<float>& vy,
                       const std::vector<float>& vz, int tile_size = kDefaultTileSize);

}  // namespace heightmarch
