#include "heightmarch/views.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "rays/batch_builder.hpp"
#include "rays/camera.hpp"
#include "util/string_format.hpp"

namespace heightmarch {
namespace {

// Deterministic draws in [0, 1), the same on every platform and standard library: splitmix64 on
// a state mixed from the seed and a stream (one stream per view), its top 53 bits.
class Draws {
 public:
  Draws(std::uint64_t seed, std::uint64_t stream)
      : state_(seed * 0x9E3779B97F4A7C15ull ^ (stream + 1) * 0xD1B54A32D192ED03ull) {}
  double next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

// Where a view of a set lies on the repeating map: turned by `turn` radians about the normal
// through the map's centre, then moved by an offset, its entry points taken modulo 1. The
// identity (a single view at seed 0) leaves every ray exactly as its camera made it. It places a
// batch's ray after the batch's gradients were taken on the camera's own rays (set_pixel_gradients):
// they turn with the ray, and neither the offset nor the wrap (a jump of 1 between neighbours,
// where the camera's continuous T has none) reaches them.
struct Placement {
  double turn = 0, du = 0, dv = 0;
  bool wrap = false;
  void operator()(RayBatch& b, std::size_t i) const {
    if (!wrap) return;
    const double c = std::cos(turn), s = std::sin(turn);
    const auto turned = [&](float& x, float& y) {
      const double tx = c * x - s * y, ty = s * x + c * y;
      x = float(tx);
      y = float(ty);
    };
    const double x = double(b.tx[i]) - 0.5, y = double(b.ty[i]) - 0.5;
    const double u = 0.5 + c * x - s * y + du, v = 0.5 + s * x + c * y + dv;
    b.tx[i] = float(u - std::floor(u));
    b.ty[i] = float(v - std::floor(v));
    turned(b.vx[i], b.vy[i]);
    turned(b.du_dx[i], b.dv_dx[i]);
    turned(b.du_dy[i], b.dv_dy[i]);
  }
};

// Places every ray of a batch made on its cameras' own rays, placement_of(i) for ray i; padding
// copies its tile's last ray again.
template <class PlacementOf>
void place_rays(RayBatch& batch, const PlacementOf& placement_of) {
  for (std::size_t i = 0; i < batch.size(); ++i) {
    if (!batch.is_padding(i)) {
      placement_of(i)(batch, i);
      continue;
    }
    for (auto* a : {&batch.tx, &batch.ty, &batch.vx, &batch.vy, &batch.vz, &batch.du_dx, &batch.dv_dx,
                    &batch.du_dy, &batch.dv_dy})
      (*a)[i] = (*a)[i - 1];
  }
}

}  // namespace

ViewSpec default_view(int width, int height) {
  if (width < 1 || height < 1 || width > kMaxViewSide || height > kMaxViewSide)
    throw InputError("view size " + std::to_string(width) + "x" + std::to_string(height) + " outside [1, " +
                     std::to_string(kMaxViewSide) + "]");
  ViewSpec view;
  view.width = width;
  view.height = height;
  return view;
}

ViewSpec sweep_view(double theta_degrees, int width, int height) {
  ViewSpec view;
  view.kind = ViewSpec::Kind::sweep;
  view.theta_degrees = float(theta_degrees);
  view.width = width;
  view.height = height;
  return view;
}

ViewSpec rays_file_view(const std::string& path) {
  ViewSpec view;
  view.kind = ViewSpec::Kind::rays_file;
  view.path = path;
  return view;
}

namespace {

// The set a window was made as (seen_as's inverse).
ViewSet set_of(const ViewSpec& view) {
  switch (view.kind) {
    case ViewSpec::Kind::tutorial:
      return ViewSet::tutorial(view.views);
    case ViewSpec::Kind::poses:
      return ViewSet::poses(view.path);
    case ViewSpec::Kind::perspective:
    case ViewSpec::Kind::sweep:
    case ViewSpec::Kind::rays_file:
      break;
  }
  return view.around ? ViewSet::around() : ViewSet::single();
}

}  // namespace

ViewSpec seen_as(ViewSpec view, const ViewSet& set) {
  const bool sweep = view.kind == ViewSpec::Kind::sweep;
  if (view.kind != ViewSpec::Kind::perspective && !sweep)
    throw InputError("a view set is made of the default view or a sweep, not " + describe(view));
  view.around = set.kind == ViewSet::Kind::around;
  view.views = 1;
  switch (set.kind) {
    case ViewSet::Kind::single:
    case ViewSet::Kind::around:
      break;
    case ViewSet::Kind::tutorial:
      if (set.frames < 1 || set.frames > kMaxSetViews)
        throw InputError("the tutorial's scene takes 1 to " + std::to_string(kMaxSetViews) + " frames, not " +
                         std::to_string(set.frames));
      [[fallthrough]];
    case ViewSet::Kind::poses:
      if (sweep) throw InputError("a sweep is seen single or around, not as the tutorial's scene or poses");
      view.kind = set.kind == ViewSet::Kind::tutorial ? ViewSpec::Kind::tutorial : ViewSpec::Kind::poses;
      view.views = set.kind == ViewSet::Kind::tutorial ? set.frames : 1;
      if (set.kind == ViewSet::Kind::poses) view.path = set.poses_file;
      break;
  }
  view.seed = set.selection_seed();
  return view;
}

ViewSpec held_out_view(const ViewSpec& view) {
  ViewSpec held_out = view;
  held_out.seed = view.seed + 1;
  return held_out;
}

bool is_view_set(const ViewSpec& view) {
  return view.fresh_rays > 0 || view.kind == ViewSpec::Kind::tutorial || view.kind == ViewSpec::Kind::poses ||
         view.around;
}

void size_views_for_rays(ViewSpec& view, double rays) {
  if (view.kind == ViewSpec::Kind::poses || view.kind == ViewSpec::Kind::rays_file) return;
  if (view.kind != ViewSpec::Kind::tutorial) {
    view.width = view.height = std::clamp(int(std::lround(std::sqrt(rays))), 1, kMaxViewSide);
    return;
  }
  // The tutorial keeps its window: under trilinear filtering the frame's size sets the level of
  // detail every ray reads. The budget takes frames of the turn instead (at most those asked, at
  // least one), by the share of a frame's pixels that see the quad's front over the turn, at a
  // coarse size.
  ViewSpec probe = view;
  probe.width = kTutorialWidth / 10;
  probe.height = kTutorialHeight / 10;
  probe.fresh_rays = 0;
  const double share =
      double(make_view_rays(probe).ray_count) / (double(probe.width) * probe.height * view.views);
  const double per_frame = double(kTutorialWidth) * kTutorialHeight * std::max(share, 1e-3);
  view.width = kTutorialWidth;
  view.height = kTutorialHeight;
  view.views = std::clamp(int(std::lround(rays / per_frame)), 1, view.views);
}

ViewSpec subpixel_view(ViewSpec view, float dx, float dy) {
  view.subpixel[0] = dx;
  view.subpixel[1] = dy;
  return view;
}

std::string describe(const ViewSpec& view) {
  if (view.fresh_rays > 0) {
    ViewSpec window = view;
    window.fresh_rays = 0;
    return "fresh " + std::to_string(view.fresh_rays) + " rays like " + describe(window);
  }
  if (view.kind == ViewSpec::Kind::rays_file) return "rays:" + view.path;
  const std::string seed =
      view.seed != set_of(view).selection_seed() ? " seed " + std::to_string(view.seed) : "";
  if (view.kind == ViewSpec::Kind::poses) return "poses:" + view.path + seed;
  const std::string size = std::to_string(view.width) + "x" + std::to_string(view.height);
  char buf[64];
  if (view.kind == ViewSpec::Kind::tutorial)
    return "tutorial:" + std::to_string(view.views) + " " + size + seed;
  if (view.kind == ViewSpec::Kind::perspective) {
    const std::string name = view.around ? "around" : "default";
    if (view.near_degrees == kDefaultNearDegrees && view.far_degrees == kDefaultFarDegrees)
      return name + " " + size + seed;
    std::snprintf(buf, sizeof buf, ":%g-%g ", view.near_degrees, view.far_degrees);
    return name + buf + size + seed;
  }
  if (view.around) {
    std::snprintf(buf, sizeof buf, "sweep:%g", view.theta_degrees);
    const std::string phi = view.phi_degrees != 270.0f ? "," + string_format("%g", view.phi_degrees) : "";
    return buf + phi + " around " + size + seed;
  }
  std::snprintf(buf, sizeof buf, "sweep:%g,%g ", view.theta_degrees, view.phi_degrees);
  return buf + size + seed;
}

namespace {

// Adds one tile's rays, pixels [x0, x1) x [y0, y1) of a view whose image lies at (left, top) of the
// batch's; ray_of(px, py) is the pixel's ray (or a miss). Inside a tile, blocks of kBlockWidth x
// kBlockHeight pixels, so packets are compact (rays.hpp).
template <class RayOf>
void add_tile(BatchBuilder& builder, const RayBatch& batch, int x0, int y0, int x1, int y1, int left, int top,
              const RayOf& ray_of) {
  for (int by = y0; by < y1; by += kBlockHeight)
    for (int bx = x0; bx < x1; bx += kBlockWidth)
      for (int py = by; py < std::min(by + kBlockHeight, y1); ++py)
        for (int px = bx; px < std::min(bx + kBlockWidth, x1); ++px)
          if (const Ray r = ray_of(px, py); r.hit)
            builder.add(
                r, std::uint32_t(top + py) * std::uint32_t(batch.image_width) + std::uint32_t(left + px));
  builder.end_tile();
}

void check_set(int views, double pixels, int tile_size, const std::string& what) {
  check_tile_size(tile_size);
  if (views < 1 || views > kMaxSetViews)
    throw InputError(std::to_string(views) + " views: a set has 1 to " + std::to_string(kMaxSetViews));
  check_memory_budget(kBytesPerRay * padding_factor(tile_size) * pixels, what);
  if (pixels >= double(kPaddingRay)) throw InputError(what + ": more pixels than a batch can number");
}

// A batch of `views` views of width x height each, side by side in its image (8 views in 4 x 2
// cells: wider than tall), tile by tile in row-major order; ray_of(k, px, py), each view's rays
// then placed by placements[k].
template <class RayOf>
RayBatch make_set(int views, int width, int height, int tile_size, const std::vector<Placement>& placements,
                  const RayOf& ray_of) {
  const int cols = std::min(views, int(std::ceil(std::sqrt(2.0 * views)))), rows = (views + cols - 1) / cols;
  check_set(views, double(cols) * width * rows * height, tile_size,
            (views > 1 ? std::to_string(views) + " views of " : std::string("a ")) + std::to_string(width) +
                "x" + std::to_string(height) + (views > 1 ? "" : " view"));
  RayBatch batch;
  batch.image_width = cols * width;
  batch.image_height = rows * height;
  BatchBuilder builder(batch);
  for (int k = 0; k < views; ++k) {
    for (int y = 0; y < height; y += tile_size)
      for (int x = 0; x < width; x += tile_size)
        add_tile(builder, batch, x, y, std::min(x + tile_size, width), std::min(y + tile_size, height),
                 (k % cols) * width, (k / cols) * height, [&](int px, int py) {
                   Ray r = ray_of(k, px, py);
                   r.view = std::uint32_t(k);
                   return r;
                 });
  }
  set_pixel_gradients(batch, width, height);
  place_rays(batch, [&](std::size_t i) { return placements[batch.view[i]]; });
  return batch;
}

// The default view or a sweep, as one view or turned around the surface. Around, every cell of
// kViewCell x kViewCell pixels of the frame is seen from an azimuth of its own, at an offset of its
// own on the repeating map: the camera turned about the normal so that the cell's centre ray looks
// from that azimuth. Each row of cells (a band of view angles) is stratified: its C cells take the
// C sectors of the circle in an order drawn at random, each at an azimuth drawn within its sector.
// So every band of angles is seen evenly from every azimuth, and position, azimuth and angle are
// independent; the frame keeps its density of pixels and its span of view angles, and a cell is
// whole packet blocks, so packets are as coherent as in one frame seen from their azimuth. A cell
// is a view of the set, numbered by row and sector; a single view's views are its tiles.
RayBatch frame_rays(const ViewSpec& view) {
  check_set(1, double(view.width) * view.height, view.tile_size,
            "a " + std::to_string(view.width) + "x" + std::to_string(view.height) + " view");
  const Camera camera = default_camera(view.near_degrees, view.far_degrees);
  const PlaneMap square;
  const double theta = view.theta_degrees * kPi / 180.0, phi = view.phi_degrees * kPi / 180.0;
  const float sweep_v[3] = {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                            float(std::cos(theta))};
  const bool sweep = view.kind == ViewSpec::Kind::sweep;
  // The ray of a pixel through its centre moved by `offset` pixels.
  const auto ray_at = [&](int px, int py, const float offset[2]) {
    const double x = px + 0.5 + offset[0], y = py + 0.5 + offset[1];
    return sweep
               ? Ray{true, float(x / view.width), float(y / view.height), sweep_v[0], sweep_v[1], sweep_v[2]}
               : camera_ray(camera, square, x, y, view.width, view.height);
  };
  const float centre_offset[2] = {0.0f, 0.0f};  // a cell's azimuth: its own centre's, in every pass
  const auto ray_of = [&](int px, int py) { return ray_at(px, py, view.subpixel); };
  const int tile = view.tile_size, tiles_x = (view.width + tile - 1) / tile;
  const int cells_x = (view.width + kViewCell - 1) / kViewCell,
            cells_y = (view.height + kViewCell - 1) / kViewCell;
  std::vector<Placement> cells(view.around ? std::size_t(cells_x) * std::size_t(cells_y) : 1);
  std::vector<std::uint32_t> cell_view(cells.size(), 0);
  if (!view.around && view.seed != 0) {  // a single view's held-out set: the same frame at another offset
    Draws draws(view.seed, 0);
    cells[0] = {0.0, draws.next(), draws.next(), true};
  }
  for (int cy = 0; view.around && cy < cells_y; ++cy) {
    // The row's cells by sector: sector j's cell is order[j], at the offset of stratum across[j] in
    // u and along[j] in v (a Latin hypercube: the row's cells spread over the map evenly).
    Draws draws(view.seed, std::uint64_t(cy));
    const auto shuffled = [&] {
      std::vector<int> order(cells_x);
      std::iota(order.begin(), order.end(), 0);
      if (view.seed != 0)
        for (int j = cells_x - 1; j > 0; --j)
          std::swap(order[j], order[std::min(j, int(draws.next() * (j + 1)))]);
      return order;
    };
    const std::vector<int> order = shuffled(), across = shuffled(), along = shuffled();
    for (int j = 0; j < cells_x; ++j) {
      const int cx = order[j];
      const Ray centre = ray_at(std::min(cx * kViewCell + kViewCell / 2, view.width - 1),
                                std::min(cy * kViewCell + kViewCell / 2, view.height - 1), centre_offset);
      Placement& place = cells[std::size_t(cy) * cells_x + cx];
      place.wrap = true;
      place.turn = phi + 2.0 * kPi * (j + (view.seed != 0 ? draws.next() : 0.0)) / cells_x -
                   std::atan2(double(centre.vy), double(centre.vx));
      if (view.seed != 0)
        place.du = (across[j] + draws.next()) / cells_x, place.dv = (along[j] + draws.next()) / cells_x;
      cell_view[std::size_t(cy) * cells_x + cx] = std::uint32_t(cy * cells_x + j);
    }
  }
  const auto cell_of = [&](int px, int py) {
    return view.around ? std::size_t(py / kViewCell) * cells_x + std::size_t(px / kViewCell) : 0;
  };
  RayBatch batch;
  batch.image_width = view.width;
  batch.image_height = view.height;
  BatchBuilder builder(batch);
  for (int y = 0; y < view.height; y += tile)
    for (int x = 0; x < view.width; x += tile)
      add_tile(builder, batch, x, y, std::min(x + tile, view.width), std::min(y + tile, view.height), 0, 0,
               [&](int px, int py) {
                 Ray r = ray_of(px, py);
                 r.view = view.around ? cell_view[cell_of(px, py)]
                                      : std::uint32_t((y / tile) * tiles_x + x / tile);
                 return r;
               });
  set_pixel_gradients(batch, view.width, view.height);
  place_rays(batch, [&](std::size_t i) {
    return cells[cell_of(int(batch.origin[i] % std::uint32_t(view.width)),
                         int(batch.origin[i] / std::uint32_t(view.width)))];
  });
  return batch;
}

RayBatch tutorial_rays(const ViewSpec& view) {
  // Frame k at (k + phase) / N of the turn: the tutorial's own frames for seed 0, another phase
  // and each frame at its own offset on the repeating map otherwise.
  const double turn_seconds = 360.0 / std::fabs(kTutorialDegreesPerSecond);
  const double phase = view.seed != 0 ? Draws(view.seed, std::uint64_t(view.views)).next() : 0.0;
  std::vector<Camera> frames;
  std::vector<Placement> offsets(std::size_t(view.views));
  for (int k = 0; k < view.views; ++k) {
    if (view.seed != 0) {
      Draws draws(view.seed, std::uint64_t(k));
      offsets[std::size_t(k)] = {0.0, draws.next(), draws.next(), true};
    }
    frames.push_back(tutorial_camera(turn_seconds * (k + phase) / view.views));
  }
  const PlaneMap quad{0.5, 0.5, 0.5, -1, 1, -1, 1, 0};
  return make_set(view.views, view.width, view.height, view.tile_size, offsets, [&](int k, int px, int py) {
    return camera_ray(frames[k], quad, px + 0.5 + view.subpixel[0], py + 0.5 + view.subpixel[1], view.width,
                      view.height);
  });
}

// Each pose's image in a cell of the largest pose's size; its pixels that see the plane, up to
// kMaxViewDegrees from the normal, each at its entry point modulo 1 (the map repeats over it).
RayBatch poses_rays(const ViewSpec& view, std::vector<std::size_t>& pose_lines) {
  const std::vector<CameraPose> poses = load_camera_poses(view.path);
  for (const CameraPose& p : poses) pose_lines.push_back(p.line);
  int width = 1, height = 1;
  for (const CameraPose& p : poses) width = std::max(width, p.width), height = std::max(height, p.height);
  std::vector<Camera> cameras;
  std::vector<Placement> offsets(poses.size(), Placement{0.0, 0.0, 0.0, true});
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (view.seed != 0) {
      Draws draws(view.seed, k);
      offsets[k].du = draws.next();
      offsets[k].dv = draws.next();
    }
    cameras.push_back(pose_camera(poses[k]));
  }
  const double inf = HUGE_VAL;
  const PlaneMap plane{0, 0, 1, -inf, inf, -inf, inf, std::cos(kMaxViewDegrees * kPi / 180.0)};
  RayBatch batch =
      make_set(int(poses.size()), width, height, view.tile_size, offsets, [&](int k, int px, int py) {
        if (px >= poses[k].width || py >= poses[k].height) return Ray{false, 0, 0, 0, 0, 0};
        return camera_ray(cameras[k], plane, px + 0.5 + view.subpixel[0], py + 0.5 + view.subpixel[1],
                          poses[k].width, poses[k].height);
      });
  if (batch.ray_count == 0)
    throw InputError(view.path + ": no pose sees the surface within " + std::to_string(int(kMaxViewDegrees)) +
                     " degrees of its normal");
  return batch;
}

// Fresh rays like a window's: each the view angle and pixel footprint of a ray of the window drawn
// at random, the azimuth uniform in [0, 360) degrees (the footprint turned with the ray, as turning
// a view about the normal turns its gradients), the entry point uniform in [0, 1)^2. So their
// errors in pixels and their trilinear levels of detail are the window's.
RayBatch fresh_rays(const ViewSpec& view) {
  const std::size_t n = view.fresh_rays;
  // Asked before anything is made: the batch, its hits and references (make_ray_list asks again,
  // the columns then held) and the nine columns it is made from (the rays' five, the footprint's four).
  check_memory_budget((kBytesPerRay * padding_factor(view.tile_size) + 9.0 * sizeof(float)) * double(n),
                      std::to_string(n) + " fresh rays");
  ViewSpec window = view;
  window.fresh_rays = 0;
  struct Source {
    float vz;
    double phi;
    float du_dx, dv_dx, du_dy, dv_dy;
  };
  std::vector<Source> sources;
  {
    const RayBatch source = make_view_rays(window);
    for (std::size_t i = 0; i < source.size(); ++i)
      if (!source.is_padding(i))
        sources.push_back({source.vz[i], std::atan2(double(source.vy[i]), double(source.vx[i])),
                           source.du_dx[i], source.dv_dx[i], source.du_dy[i], source.dv_dy[i]});
  }
  if (sources.empty()) throw InputError(describe(window) + ": no rays to draw view angles from");
  std::vector<float> tx(n), ty(n), vx(n), vy(n), vz(n);
  std::vector<std::array<float, 4>> footprint(n);
  Draws draws(view.seed, 0xF2E5'0000'0000ull);  // a stream no view of a set uses
  for (std::size_t i = 0; i < n; ++i) {
    const Source& from =
        sources[std::min(sources.size() - 1, std::size_t(draws.next() * double(sources.size())))];
    const double cos_theta = from.vz;
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const double phi = 2.0 * kPi * draws.next();
    tx[i] = float(draws.next());
    ty[i] = float(draws.next());
    vx[i] = float(sin_theta * std::cos(phi));
    vy[i] = float(sin_theta * std::sin(phi));
    vz[i] = float(cos_theta);
    const double c = std::cos(phi - from.phi), s = std::sin(phi - from.phi);
    footprint[i] = {float(c * from.du_dx - s * from.dv_dx), float(s * from.du_dx + c * from.dv_dx),
                    float(c * from.du_dy - s * from.dv_dy), float(s * from.du_dy + c * from.dv_dy)};
  }
  RayBatch batch = make_ray_list(tx, ty, vx, vy, vz, view.tile_size);
  // Each ray's footprint by its row; padding copies its tile's last ray, as for a view.
  std::array<float, 4> last{};
  for (std::size_t i = 0; i < batch.size(); ++i) {
    if (!batch.is_padding(i)) last = footprint[batch.origin[i]];
    batch.du_dx[i] = last[0];
    batch.dv_dx[i] = last[1];
    batch.du_dy[i] = last[2];
    batch.dv_dy[i] = last[3];
  }
  return batch;
}

}  // namespace

RayBatch make_view_rays(const ViewSpec& view) {
  std::vector<std::size_t> pose_lines;  // poses: each pose's line in its file
  RayBatch batch;
  if (view.fresh_rays > 0) {
    batch = fresh_rays(view);
  } else if (view.kind == ViewSpec::Kind::rays_file) {
    batch = load_rays_csv(view.path, view.tile_size);
  } else if (view.kind == ViewSpec::Kind::tutorial) {
    batch = tutorial_rays(view);
  } else if (view.kind == ViewSpec::Kind::poses) {
    batch = poses_rays(view, pose_lines);
  } else {
    batch = frame_rays(view);
  }
  // The one check of every batch, whatever made it: a ray no kernel can take (a pose whose rays meet
  // the plane beyond a float's range has an infinite T, NaN gradients and a NaN wrap) is refused,
  // naming where it came from.
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const std::string fault = ray_fault(batch, i);
    if (fault.empty()) continue;
    const std::uint32_t k = batch.view[i], origin = batch.origin[i];
    std::string where = describe(view) + ": ray " + std::to_string(i + 1);
    if (view.fresh_rays == 0 && view.kind == ViewSpec::Kind::poses)
      where = view.path + ":" + std::to_string(pose_lines[k]) + ": pose " + std::to_string(k + 1);
    else if (view.fresh_rays == 0 && view.kind == ViewSpec::Kind::tutorial)
      where = describe(view) + ": frame " + std::to_string(k + 1);
    else if (view.fresh_rays == 0 && view.kind != ViewSpec::Kind::rays_file && origin != kPaddingRay)
      where = describe(view) + ": the ray of pixel (" +
              std::to_string(origin % std::uint32_t(batch.image_width)) + ", " +
              std::to_string(origin / std::uint32_t(batch.image_width)) + ")";
    throw InputError(where + ": " + fault + ": its rays cannot be traced");
  }
  return batch;
}

}  // namespace heightmarch
