#pragma once
// The views a run measures (docs/measures.md#view-sets), as typed values: a frame (the perspective
// view, a sweep of one V, a rays file) and the set of views of it a window takes (ViewSet), and
// the ray batches they make (rays.hpp). Text becomes these types once, at the edge
// (parse_view(), parse_view_set()); inside the program they are built from the types.
#include <cstddef>
#include <cstdint>
#include <string>

#include "heightmarch/rays.hpp"

namespace heightmarch {

// The default view's span of view angles, degrees from the normal.
inline constexpr float kDefaultNearDegrees = 30.0f, kDefaultFarDegrees = 80.0f;
inline constexpr float kMaxViewDegrees = 89.0f;

// LearnOpenGL's scene: kTutorialFrames frames of one turn unless asked, in its 800 x 600 window.
inline constexpr int kTutorialFrames = 16;
inline constexpr int kTutorialWidth = 800, kTutorialHeight = 600;
inline constexpr int kMaxSetViews = 4096;
// A view set around the surface turns each cell of kViewCell x kViewCell pixels to its own azimuth
// (views.cpp): whole blocks, so no packet spans two azimuths.
inline constexpr int kViewCell = 8;
static_assert(kViewCell % kBlockWidth == 0 && kViewCell % kBlockHeight == 0);

// Which views of a frame a window measures: the single frame, the frame seen around the surface
// (every kViewCell cell of it from an azimuth and at an offset of its own), LearnOpenGL's rotating
// quad at `frames` frames of one turn, or a user's camera poses from a CSV file (camera_poses.hpp).
// Each has its selection seed (selection_seed()): around draws its azimuths and offsets at seed 1;
// the others are taken as they are (seed 0).
struct ViewSet {
  enum class Kind { single, around, tutorial, poses };
  Kind kind = Kind::single;
  int frames = 1;          // tutorial: the frames of one turn
  std::string poses_file;  // poses: the camera-pose CSV

  static ViewSet single() { return {}; }
  static ViewSet around() { return {Kind::around, 1, {}}; }
  static ViewSet tutorial(int frames = kTutorialFrames) { return {Kind::tutorial, frames, {}}; }
  static ViewSet poses(std::string file) { return {Kind::poses, 1, std::move(file)}; }
  std::uint32_t selection_seed() const { return kind == Kind::around ? 1u : 0u; }
  friend bool operator==(const ViewSet&, const ViewSet&) = default;
};

// Where a batch's rays come from: the perspective benchmark view, a sweep of one V over a grid
// of T, a CSV file of rays (width x height is then rows x 1, known once loaded), or a view set:
// the perspective view or a sweep seen around the surface (each cell of its frame from its own
// azimuth), LearnOpenGL's rotating quad at `views` frames of one turn, or a user's camera poses
// (frames and poses side by side in the batch's image). A tile never spans two views. Built by
// default_view(), sweep_view(), rays_file_view() and seen_as().
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
  // perspective and sweep: seen around the surface, every cell of the frame from an azimuth and
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
  // Each pixel's ray through its centre moved by this many pixels right and down, in [-0.5, 0.5)
  // (subpixel_view); a set's views keep their azimuths and offsets.
  float subpixel[2] = {0.0f, 0.0f};
  friend bool operator==(const ViewSpec&, const ViewSpec&) = default;
};

// The default view of width x height pixels at the default span of angles; throws InputError for
// a side outside [1, kMaxViewSide].
ViewSpec default_view(int width, int height);
ViewSpec sweep_view(double theta_degrees, int width, int height);  // at the default azimuth
ViewSpec rays_file_view(const std::string& path);
// The view with every pixel's ray moved (dx, dy) pixels from its pixel's centre: one pass of n x n
// subpixel rays a pixel (a perspective view, the tutorial's, a pose file's; a sweep's entry points).
ViewSpec subpixel_view(ViewSpec view, float dx, float dy);

// The perspective view (its span and size kept) or a sweep (single or around only) seen as `set`:
// its kind, around, views, path and the set's selection seed. Throws InputError for a set the
// frame cannot take or a tutorial's frames outside [1, kMaxSetViews].
ViewSpec seen_as(ViewSpec frame, const ViewSet& set);
// The held-out set of a window: the same window drawn at seed + 1 (other azimuths within their
// sectors in another order, other offsets, another phase of the tutorial's turn).
ViewSpec held_out_view(const ViewSpec& view);
// More than one view, or fresh rays: a figure over it is another series than a single view's.
bool is_view_set(const ViewSpec& view);
// Sizes a window so that it holds about `rays` rays: a square frame; the tutorial's 800 x 600
// window at as many frames of the turn as hold them (at most those it has, at least one: the
// frame's size sets the level of detail under trilinear filtering). A pose file keeps its poses'
// sizes.
void size_views_for_rays(ViewSpec& view, double rays);

// "default 1024x1024", "default:45-85 1024x1024" (angles other than 30-80), "sweep:70,270 128x128",
// "rays:FILE"; sets: "around 1024x1024", "around:45-85 1024x1024", "sweep:70 around 128x128",
// "tutorial:16 800x600", "poses:FILE", then " seed N" where
// the seed is not the window's selection seed, and "fresh 100000 rays like ..." for fresh rays
std::string describe(const ViewSpec& view);

// The default view: a perspective camera looking at the plane so view angles span near_degrees
// (near edge) to far_degrees (far edge); at 30 and 80, from (0.5, -0.113, 0.196). The sweep view:
// one fixed V over a width x height grid of T at pixel centres of [0,1]^2. A rays_file view loads
// its CSV (load_rays_csv).
RayBatch make_view_rays(const ViewSpec& view);

// The names a user gives (view_names.cpp), each turned into its typed value once; each throws
// InputError naming the text, not the option it came from (the programs add that).
// "default", "default:NEAR-FAR" (the perspective view's span of angles) or "sweep:THETA[,PHI]"
// (degrees), at width x height.
ViewSpec parse_view(const std::string& text, int width, int height);
// "NEAR-FAR" in degrees, 0 <= NEAR < FAR <= kMaxViewDegrees, into the view.
void parse_view_angles(const std::string& text, ViewSpec& view);
// "single", "around", "tutorial[:N]" (N in [1, kMaxSetViews]) or a camera-pose FILE.csv.
ViewSet parse_view_set(const std::string& text);

}  // namespace heightmarch
