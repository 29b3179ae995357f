#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/rays.hpp"
#include "rays/camera_poses.hpp"
#include "util/string_format.hpp"

namespace heightmarch {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinViewZ = 5e-7;     // V.z below this is a grazing ray: rejected
constexpr float kMaxRayOrigin = 1e6f;  // |T.x|, |T.y|
// LearnOpenGL's parallax scene: the quad turns at 10 degrees a second (glfwGetTime() * -10.0f)
// about normalize(1, 0, 1), seen from (0, 0, 3) with a 45 degree field of view at 800 x 600.
constexpr double kTutorialDegreesPerSecond = -10.0;
constexpr double kTutorialEyeZ = 3.0, kTutorialFovDegrees = 45.0;

struct Vec3 {
  double x = 0, y = 0, z = 0;
};
Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 normalized(const Vec3& a) {
  const double len = std::sqrt(dot(a, a));
  return {a.x / len, a.y / len, a.z / len};
}

// A pinhole camera in the surface's frame (the surface is the plane z = 0, its normal +z): the
// eye, the image's unit axes and the forward direction, tan of half the vertical field of view.
struct Camera {
  Vec3 eye, right, up, forward;
  double tan_half_fov = 1;
};

// Where the plane shows the map: within [x0, x1] x [y0, y1], uv = (u0, v0) + scale (x, y). The
// pose files' plane is unbounded (every pixel that sees it, up to kMaxViewDegrees from the normal).
struct PlaneMap {
  double u0 = 0, v0 = 0, scale = 1;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double min_view_z = 0;  // rays more grazing than this are dropped
};

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

// The default camera: the near edge of the plane (v = 0) seen at the near angle from the normal
// (30 degrees unless asked), the far edge (v = 1) at the far angle (80), on the centre line; eye
// height h and distance a before the near edge follow from tan near = a / h and tan far = (1 + a) / h.
Camera default_camera(const ViewSpec& view) {
  const double near_angle = view.near_degrees * kPi / 180.0, far_angle = view.far_degrees * kPi / 180.0;
  const double height = 1.0 / (std::tan(far_angle) - std::tan(near_angle));
  const double back = std::tan(near_angle) * height;
  const double pitch = 0.5 * (far_angle + near_angle);  // forward, from straight down
  Camera c;
  c.eye = {0.5, -back, height};
  c.right = {1, 0, 0};
  c.up = {0, std::cos(pitch), std::sin(pitch)};
  c.forward = {0, std::sin(pitch), -std::cos(pitch)};
  c.tan_half_fov = std::tan(0.5 * (far_angle - near_angle));
  return c;
}

struct Ray {
  bool hit;
  float tx, ty, vx, vy, vz;
  std::uint32_t view = 0;  // of its set (RayBatch::view)
};

Ray camera_ray(const Camera& cam, const PlaneMap& plane, int px, int py, int width, int height) {
  const double sx = (2.0 * (px + 0.5) / width - 1.0) * cam.tan_half_fov * double(width) / double(height);
  const double sy = (1.0 - 2.0 * (py + 0.5) / height) * cam.tan_half_fov;  // row 0 = top of the image
  const double dx = cam.forward.x + sx * cam.right.x + sy * cam.up.x;
  const double dy = cam.forward.y + sx * cam.right.y + sy * cam.up.y;
  const double dz = cam.forward.z + sx * cam.right.z + sy * cam.up.z;
  if (dz >= 0.0) return {false, 0, 0, 0, 0, 0};
  const double t = -cam.eye.z / dz;
  const double x = cam.eye.x + t * dx, y = cam.eye.y + t * dy;
  if (x < plane.x0 || x > plane.x1 || y < plane.y0 || y > plane.y1) return {false, 0, 0, 0, 0, 0};
  const double ex = cam.eye.x - x, ey = cam.eye.y - y, ez = cam.eye.z;
  const double len = std::sqrt(ex * ex + ey * ey + ez * ez);
  if (ez / len < plane.min_view_z) return {false, 0, 0, 0, 0, 0};
  return {true,
          float(plane.u0 + plane.scale * x),
          float(plane.v0 + plane.scale * y),
          float(ex / len),
          float(ey / len),
          float(ez / len)};
}

// A camera given in world space, seen from a surface frame (origin o, orthonormal tangent,
// bitangent and normal): the same camera in that frame's coordinates.
Camera in_frame(const Camera& world, const Vec3& o, const Vec3& t, const Vec3& b, const Vec3& n) {
  const auto axis = [&](const Vec3& v) { return Vec3{dot(v, t), dot(v, b), dot(v, n)}; };
  Camera c = world;
  c.eye = axis(world.eye - o);
  c.right = axis(world.right);
  c.up = axis(world.up);
  c.forward = axis(world.forward);
  return c;
}

// LearnOpenGL's scene at `seconds` into the turn, in the quad's frame: the quad spans [-1, 1]^2
// with uv (x + 1) / 2, (y + 1) / 2, tangent +x and bitangent +y of its model matrix. An eye behind
// the quad sees its back face, which is dropped (every ray then misses).
Camera tutorial_camera(double seconds) {
  const double angle = kTutorialDegreesPerSecond * seconds * kPi / 180.0;
  const double k = 1.0 / std::sqrt(2.0);  // normalize(1, 0, 1)
  const double c = std::cos(angle), s = std::sin(angle), C = 1.0 - c;
  const double ax = k, ay = 0, az = k;
  // Rodrigues' rotation matrix, its columns: the quad's tangent, bitangent and normal in the world.
  const Vec3 t{c + ax * ax * C, ay * ax * C + az * s, az * ax * C - ay * s};
  const Vec3 b{ax * ay * C - az * s, c + ay * ay * C, az * ay * C + ax * s};
  const Vec3 n{ax * az * C + ay * s, ay * az * C - ax * s, c + az * az * C};
  Camera world;
  world.eye = {0, 0, kTutorialEyeZ};
  world.right = {1, 0, 0};
  world.up = {0, 1, 0};
  world.forward = {0, 0, -1};
  world.tan_half_fov = std::tan(0.5 * kTutorialFovDegrees * kPi / 180.0);
  return in_frame(world, {0, 0, 0}, t, b, n);
}

Camera pose_camera(const CameraPose& p) {
  Camera c;
  c.eye = {p.eye[0], p.eye[1], p.eye[2]};
  c.forward = normalized(Vec3{p.target[0], p.target[1], p.target[2]} - c.eye);
  c.right = normalized(cross(c.forward, {p.up[0], p.up[1], p.up[2]}));
  c.up = cross(c.right, c.forward);
  c.tan_half_fov = std::tan(0.5 * p.fov_degrees * kPi / 180.0);
  return c;
}

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

// Appends one tile's rays, padded with copies of its last ray to a multiple of kRayAlignment.
class BatchBuilder {
 public:
  explicit BatchBuilder(RayBatch& batch) : batch_(batch) {}
  void add(const Ray& r, std::uint32_t origin) {
    batch_.tx.push_back(r.tx);
    batch_.ty.push_back(r.ty);
    batch_.vx.push_back(r.vx);
    batch_.vy.push_back(r.vy);
    batch_.vz.push_back(r.vz);
    for (auto* g : {&batch_.du_dx, &batch_.dv_dx, &batch_.du_dy, &batch_.dv_dy}) g->push_back(0.0f);
    batch_.origin.push_back(origin);
    batch_.view.push_back(r.view);
    batch_.views = std::max(batch_.views, r.view + 1);
    ++batch_.ray_count;
  }
  void end_tile() {
    const std::size_t begin = batch_.tile_offsets.back();
    if (batch_.size() == begin) return;  // no ray in this tile
    while (batch_.size() % kRayAlignment != 0) {
      const std::size_t last = batch_.size() - 1;
      add({true, batch_.tx[last], batch_.ty[last], batch_.vx[last], batch_.vy[last], batch_.vz[last],
           batch_.view[last]},
          kPaddingRay);
      --batch_.ray_count;
    }
    batch_.tile_offsets.push_back(batch_.size());
  }

 private:
  RayBatch& batch_;
};

void check_tile_size(int tile_size) {
  if (tile_size < 1 || tile_size > 4096)
    throw InputError("tile size " + std::to_string(tile_size) + " outside [1, 4096]");
}

}  // namespace

ViewSpec parse_view(const std::string& text, int width, int height) {
  if (width < 1 || height < 1 || width > kMaxViewSide || height > kMaxViewSide)
    throw InputError("view size " + std::to_string(width) + "x" + std::to_string(height) + " outside [1, " +
                     std::to_string(kMaxViewSide) + "]");
  ViewSpec view;
  view.width = width;
  view.height = height;
  if (text == "default") return view;
  if (text.rfind("default:", 0) == 0) {
    parse_view_angles(text.substr(8), view);
    return view;
  }
  const std::string prefix = "sweep:";
  if (text.rfind(prefix, 0) != 0)
    throw InputError("unknown view '" + text + "' (default, default:NEAR-FAR or sweep:THETA[,PHI])");
  view.kind = ViewSpec::Kind::sweep;
  const std::string args = text.substr(prefix.size());
  const auto comma = args.find(',');
  try {
    std::size_t used = 0;
    const std::string theta = args.substr(0, comma);
    view.theta_degrees = std::stof(theta, &used);
    if (used != theta.size()) throw std::invalid_argument("trailing");
    if (comma != std::string::npos) {
      const std::string phi = args.substr(comma + 1);
      view.phi_degrees = std::stof(phi, &used);
      if (used != phi.size()) throw std::invalid_argument("trailing");
    }
  } catch (const std::logic_error&) {
    throw InputError("view '" + text + "': THETA and PHI must be numbers in degrees");
  }
  if (!(view.theta_degrees >= 0.0f && view.theta_degrees <= 89.0f))
    throw InputError("view '" + text + "': THETA must be in [0, 89] degrees");
  if (!std::isfinite(view.phi_degrees))
    throw InputError("view '" + text + "': PHI must be a finite number of degrees");
  return view;
}

void parse_view_angles(const std::string& text, ViewSpec& view) {
  const auto dash = text.find('-', 1);
  float near = 0, far = 0;
  try {
    if (dash == std::string::npos) throw std::invalid_argument("no dash");
    std::size_t used_near = 0, used_far = 0;
    const std::string a = text.substr(0, dash), b = text.substr(dash + 1);
    near = std::stof(a, &used_near);
    far = std::stof(b, &used_far);
    if (used_near != a.size() || used_far != b.size()) throw std::invalid_argument("trailing");
  } catch (const std::logic_error&) {
    throw InputError("view angles '" + text + "' must be NEAR-FAR in degrees, e.g. 30-80");
  }
  if (!(near >= 0.0f && near < far && far <= kMaxViewDegrees))
    throw InputError("view angles '" + text + "' must satisfy 0 <= NEAR < FAR <= " +
                     std::to_string(int(kMaxViewDegrees)) + " degrees");
  view.near_degrees = near;
  view.far_degrees = far;
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

// The seed a window is measured at (held_out_view adds one): the set around the surface draws its
// azimuths and offsets; the single view, the tutorial's scene and a user's poses are taken as
// they are.
std::uint32_t selection_seed(const ViewSpec& view) { return view.around ? 1u : 0u; }

}  // namespace

void apply_views(const std::string& text, ViewSpec& view) {
  const bool sweep = view.kind == ViewSpec::Kind::sweep;
  if (view.kind != ViewSpec::Kind::perspective && !sweep)
    throw InputError("--views applies to the default view or a sweep");
  view.around = text == "around";
  view.views = 1;
  if (text != "single" && !view.around) {
    if (sweep) throw InputError("--views '" + text + "': a sweep is seen single or around");
    const std::string tutorial = "tutorial";
    if (text == tutorial || text.rfind(tutorial + ":", 0) == 0) {
      view.kind = ViewSpec::Kind::tutorial;
      view.views = kTutorialFrames;
      const std::string number = text.substr(std::min(text.size(), tutorial.size() + 1));
      const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), view.views);
      if (text != tutorial && (number.empty() || ec != std::errc() || end != number.data() + number.size() ||
                               view.views < 1 || view.views > kMaxSetViews))
        throw InputError("--views '" + text + "': tutorial:N takes a whole number of frames N in [1, " +
                         std::to_string(kMaxSetViews) + "]");
    } else if (text.size() > 4 && text.compare(text.size() - 4, 4, ".csv") == 0) {
      view.kind = ViewSpec::Kind::poses;
      view.path = text;
    } else {
      throw InputError("unknown --views '" + text +
                       "' (single, around, tutorial[:N] or a camera-pose FILE.csv)");
    }
  }
  view.seed = selection_seed(view);
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
  // The share of a frame's pixels that see the quad's front over the turn, at a coarse size.
  ViewSpec probe = view;
  probe.width = kTutorialWidth / 10;
  probe.height = kTutorialHeight / 10;
  probe.fresh_rays = 0;
  const double share =
      double(make_view_rays(probe).ray_count) / (double(probe.width) * probe.height * view.views);
  const double pixels = rays / view.views / std::max(share, 1e-3);
  view.width = std::clamp(int(std::lround(std::sqrt(pixels * 4.0 / 3.0))), 1, kMaxViewSide);
  view.height = std::clamp(int(std::lround(view.width * 0.75)), 1, kMaxViewSide);
}

std::string describe(const ViewSpec& view) {
  if (view.fresh_rays > 0) {
    ViewSpec window = view;
    window.fresh_rays = 0;
    return "fresh " + std::to_string(view.fresh_rays) + " rays like " + describe(window);
  }
  if (view.kind == ViewSpec::Kind::rays_file) return "rays:" + view.path;
  const std::string seed = view.seed != selection_seed(view) ? " seed " + std::to_string(view.seed) : "";
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
  const Camera camera = default_camera(view);
  const PlaneMap square;
  const double theta = view.theta_degrees * kPi / 180.0, phi = view.phi_degrees * kPi / 180.0;
  const float sweep_v[3] = {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                            float(std::cos(theta))};
  const bool sweep = view.kind == ViewSpec::Kind::sweep;
  const auto ray_of = [&](int px, int py) {
    return sweep ? Ray{true,
                       float((px + 0.5) / view.width),
                       float((py + 0.5) / view.height),
                       sweep_v[0],
                       sweep_v[1],
                       sweep_v[2]}
                 : camera_ray(camera, square, px, py, view.width, view.height);
  };
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
      const Ray centre = ray_of(std::min(cx * kViewCell + kViewCell / 2, view.width - 1),
                                std::min(cy * kViewCell + kViewCell / 2, view.height - 1));
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
    return camera_ray(frames[k], quad, px, py, view.width, view.height);
  });
}

// Each pose's image in a cell of the largest pose's size; its pixels that see the plane, up to
// kMaxViewDegrees from the normal, each at its entry point modulo 1 (the map repeats over it).
RayBatch poses_rays(const ViewSpec& view) {
  const std::vector<CameraPose> poses = load_camera_poses(view.path);
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
        return camera_ray(cameras[k], plane, px, py, poses[k].width, poses[k].height);
      });
  if (batch.ray_count == 0)
    throw InputError(view.path + ": no pose sees the surface within " + std::to_string(int(kMaxViewDegrees)) +
                     " degrees of its normal");
  return batch;
}

// Fresh rays like a window's: each view angle that of a ray of the window drawn at random, the
// azimuth uniform in [0, 360) degrees, the entry point uniform in [0, 1)^2.
RayBatch fresh_rays(const ViewSpec& view) {
  ViewSpec window = view;
  window.fresh_rays = 0;
  std::vector<float> cosines;
  {
    const RayBatch source = make_view_rays(window);
    for (std::size_t i = 0; i < source.size(); ++i)
      if (!source.is_padding(i)) cosines.push_back(source.vz[i]);
  }
  if (cosines.empty()) throw InputError(describe(window) + ": no rays to draw view angles from");
  const std::size_t n = view.fresh_rays;
  std::vector<float> tx(n), ty(n), vx(n), vy(n), vz(n);
  Draws draws(view.seed, 0xF2E5'0000'0000ull);  // a stream no view of a set uses
  for (std::size_t i = 0; i < n; ++i) {
    const double cos_theta =
        cosines[std::min(cosines.size() - 1, std::size_t(draws.next() * double(cosines.size())))];
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const double phi = 2.0 * kPi * draws.next();
    tx[i] = float(draws.next());
    ty[i] = float(draws.next());
    vx[i] = float(sin_theta * std::cos(phi));
    vy[i] = float(sin_theta * std::sin(phi));
    vz[i] = float(cos_theta);
  }
  return make_ray_list(tx, ty, vx, vy, vz, view.tile_size);
}

}  // namespace

RayBatch make_view_rays(const ViewSpec& view) {
  if (view.fresh_rays > 0) return fresh_rays(view);
  switch (view.kind) {
    case ViewSpec::Kind::rays_file:
      return load_rays_csv(view.path, view.tile_size);
    case ViewSpec::Kind::tutorial:
      return tutorial_rays(view);
    case ViewSpec::Kind::poses:
      return poses_rays(view);
    case ViewSpec::Kind::perspective:
    case ViewSpec::Kind::sweep:
      break;
  }
  return frame_rays(view);
}

void set_pixel_gradients(RayBatch& rays, int frame_width, int frame_height) {
  const std::size_t width = std::size_t(rays.image_width), height = std::size_t(rays.image_height);
  check_memory_budget(4.0 * double(width) * double(height), "the pixel grid of a view");
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> ray_at(width * height, kNone);  // the ray of each pixel
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    if (rays.origin[i] >= width * height)
      throw std::logic_error("a ray's pixel lies outside its view's grid");
    ray_at[rays.origin[i]] = std::uint32_t(i);
  }
  // T's change to the next pixel along one axis (step: 1 pixel in x, or a row in y) at pixel p,
  // its coordinate c along that axis of n pixels in frames of f: towards the quad partner (quads
  // start at the frame's edge), else the other side; never into another frame.
  const auto gradient = [&](std::size_t p, std::size_t c, std::size_t n, std::size_t f, std::size_t step,
                            float& du, float& dv) {
    const std::size_t self = ray_at[p], local = c % f;
    for (const bool up : {local % 2 == 0, local % 2 != 0}) {
      if (up ? c + 1 >= n || local + 1 >= f : local == 0) continue;
      const std::size_t other = ray_at[up ? p + step : p - step];
      if (other == kNone) continue;
      const std::size_t from = up ? self : other, to = up ? other : self;
      du = rays.tx[to] - rays.tx[from];
      dv = rays.ty[to] - rays.ty[from];
      return;
    }
    du = dv = 0.0f;
  };
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) {  // a copy of its tile's last ray (BatchBuilder)
      rays.du_dx[i] = rays.du_dx[i - 1];
      rays.dv_dx[i] = rays.dv_dx[i - 1];
      rays.du_dy[i] = rays.du_dy[i - 1];
      rays.dv_dy[i] = rays.dv_dy[i - 1];
      continue;
    }
    const std::size_t p = rays.origin[i], x = p % width, y = p / width;
    gradient(p, x, width, std::size_t(frame_width), 1, rays.du_dx[i], rays.dv_dx[i]);
    gradient(p, y, height, std::size_t(frame_height), width, rays.du_dy[i], rays.dv_dy[i]);
  }
}

void check_rays(const RayBatch& rays) {
  const std::size_t n = rays.tx.size();
  for (const auto* a :
       {&rays.ty, &rays.vx, &rays.vy, &rays.vz, &rays.du_dx, &rays.dv_dx, &rays.du_dy, &rays.dv_dy})
    if (a->size() != n) throw InputError("a ray batch whose arrays differ in length");
  const auto within = [](float x) { return std::isfinite(x) && std::fabs(x) <= kMaxRayOrigin; };
  for (std::size_t i = 0; i < n; ++i) {
    const bool finite = within(rays.tx[i]) && within(rays.ty[i]) && std::isfinite(rays.vx[i]) &&
                        std::isfinite(rays.vy[i]) && std::isfinite(rays.vz[i]) && within(rays.du_dx[i]) &&
                        within(rays.dv_dx[i]) && within(rays.du_dy[i]) && within(rays.dv_dy[i]);
    if (!finite || !(rays.vz[i] > 0.0f))
      throw InputError("ray " + std::to_string(i + 1) +
                       " of the batch: not finite, |T| or a gradient beyond 1e6, or V.z <= 0");
  }
}

RayBatch make_ray_list(const std::vector<float>& tx, const std::vector<float>& ty,
                       const std::vector<float>& vx, const std::vector<float>& vy,
                       const std::vector<float>& vz, int tile_size) {
  check_tile_size(tile_size);
  check_memory_budget(kBytesPerRay * padding_factor(tile_size) * double(tx.size()),
                      std::to_string(tx.size()) + " rays");
  RayBatch batch;
  batch.image_width = int(tx.size());
  batch.image_height = 1;
  BatchBuilder builder(batch);
  const std::size_t per_tile = std::size_t(tile_size) * std::size_t(tile_size);
  for (std::size_t i = 0; i < tx.size(); ++i) {
    const auto ray = [i] { return "ray " + std::to_string(i + 1); };  // counted from 1, as every message does
    const double len = std::sqrt(double(vx[i]) * vx[i] + double(vy[i]) * vy[i] + double(vz[i]) * vz[i]);
    // Compared as stored (a float): V.z = 5e-7 exactly passes whatever the rounding of |V|.
    const float z = float(vz[i] / len);
    if (!std::isfinite(len) || !std::isfinite(tx[i]) || !std::isfinite(ty[i]))
      throw InputError(ray() + ": not finite");
    if (len == 0.0) throw InputError(ray() + ": V is the zero vector");
    if (!(z >= float(kMinViewZ))) {
      char value[32];
      std::snprintf(value, sizeof value, "%.9g", double(z));
      throw InputError(ray() + ": V.z = " + value +
                       " after normalisation, must be >= 5e-7 (a ray from below or grazing the plane)");
    }
    if (std::fabs(tx[i]) > kMaxRayOrigin || std::fabs(ty[i]) > kMaxRayOrigin)
      throw InputError(ray() + ": |T| beyond 1e6");
    builder.add({true, tx[i], ty[i], float(vx[i] / len), float(vy[i] / len), z, std::uint32_t(i / per_tile)},
                std::uint32_t(i));
    if ((i + 1) % per_tile == 0) builder.end_tile();
  }
  builder.end_tile();
  return batch;
}

}  // namespace heightmarch
