#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/rays.hpp"

namespace heightmarch {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinViewZ = 5e-7;  // V.z below this is a grazing ray: rejected
constexpr float kMaxRayOrigin = 1e6f;  // |T.x|, |T.y|

// The default camera: the near edge of the plane (v = 0) seen at the near angle from the normal
// (30 degrees unless asked), the far edge (v = 1) at the far angle (80), on the centre line; eye
// height h and distance a before the near edge follow from tan near = a / h and tan far = (1 + a) / h.
struct DefaultCamera {
  explicit DefaultCamera(const ViewSpec& view)
      : near_angle(view.near_degrees * kPi / 180.0), far_angle(view.far_degrees * kPi / 180.0) {}
  double near_angle, far_angle;
  double height = 1.0 / (std::tan(far_angle) - std::tan(near_angle));
  double back = std::tan(near_angle) * height;
  double eye[3] = {0.5, -back, height};
  double half_fov = 0.5 * (far_angle - near_angle);
  double pitch = 0.5 * (far_angle + near_angle);  // forward, from straight down
};

struct Ray {
  bool hit;
  float tx, ty, vx, vy, vz;
};

Ray perspective_ray(const DefaultCamera& cam, int px, int py, int width, int height) {
  const double tan_half = std::tan(cam.half_fov);
  const double sx = (2.0 * (px + 0.5) / width - 1.0) * tan_half * double(width) / double(height);
  const double sy = (1.0 - 2.0 * (py + 0.5) / height) * tan_half;  // row 0 = far edge
  // forward = (0, sin pitch, -cos pitch), up = (0, cos pitch, sin pitch), right = +x.
  const double dx = sx;
  const double dy = std::sin(cam.pitch) + sy * std::cos(cam.pitch);
  const double dz = -std::cos(cam.pitch) + sy * std::sin(cam.pitch);
  if (dz >= 0.0) return {false, 0, 0, 0, 0, 0};
  const double t = -cam.eye[2] / dz;
  const double x = cam.eye[0] + t * dx, y = cam.eye[1] + t * dy;
  if (x < 0.0 || x > 1.0 || y < 0.0 || y > 1.0) return {false, 0, 0, 0, 0, 0};
  const double ex = cam.eye[0] - x, ey = cam.eye[1] - y, ez = cam.eye[2];
  const double len = std::sqrt(ex * ex + ey * ey + ez * ez);
  return {true, float(x), float(y), float(ex / len), float(ey / len), float(ez / len)};
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
    ++batch_.ray_count;
  }
  void end_tile() {
    const std::size_t begin = batch_.tile_offsets.back();
    if (batch_.size() == begin) return;  // no ray in this tile
    while (batch_.size() % kRayAlignment != 0) {
      const std::size_t last = batch_.size() - 1;
      add({true, batch_.tx[last], batch_.ty[last], batch_.vx[last], batch_.vy[last], batch_.vz[last]},
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
  view.rays_path = path;
  return view;
}

std::string describe(const ViewSpec& view) {
  if (view.kind == ViewSpec::Kind::rays_file) return "rays:" + view.rays_path;
  const std::string size = std::to_string(view.width) + "x" + std::to_string(view.height);
  char buf[64];
  if (view.kind == ViewSpec::Kind::perspective) {
    if (view.near_degrees == kDefaultNearDegrees && view.far_degrees == kDefaultFarDegrees)
      return "default " + size;
    std::snprintf(buf, sizeof buf, "default:%g-%g ", view.near_degrees, view.far_degrees);
    return buf + size;
  }
  std::snprintf(buf, sizeof buf, "sweep:%g,%g ", view.theta_degrees, view.phi_degrees);
  return buf + size;
}

RayBatch make_view_rays(const ViewSpec& view) {
  if (view.kind == ViewSpec::Kind::rays_file) return load_rays_csv(view.rays_path, view.tile_size);
  const int tile_size = view.tile_size;
  check_tile_size(tile_size);
  check_memory_budget(kBytesPerRay * padding_factor(tile_size) * view.width * view.height,
                      "a " + std::to_string(view.width) + "x" + std::to_string(view.height) + " view");
  RayBatch batch;
  batch.image_width = view.width;
  batch.image_height = view.height;
  const DefaultCamera camera(view);
  const double theta = view.theta_degrees * kPi / 180.0, phi = view.phi_degrees * kPi / 180.0;
  const float sweep_v[3] = {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                            float(std::cos(theta))};
  BatchBuilder builder(batch);
  // Tiles in row-major order; inside a tile, blocks of kBlockWidth x kBlockHeight pixels, so
  // packets are compact (rays.hpp).
  for (int ty0 = 0; ty0 < view.height; ty0 += tile_size)
    for (int tx0 = 0; tx0 < view.width; tx0 += tile_size) {
      const int ty1 = std::min(ty0 + tile_size, view.height), tx1 = std::min(tx0 + tile_size, view.width);
      for (int by = ty0; by < ty1; by += kBlockHeight)
        for (int bx = tx0; bx < tx1; bx += kBlockWidth)
          for (int py = by; py < std::min(by + kBlockHeight, ty1); ++py)
            for (int px = bx; px < std::min(bx + kBlockWidth, tx1); ++px) {
              const std::uint32_t pixel = std::uint32_t(py) * std::uint32_t(view.width) + std::uint32_t(px);
              if (view.kind == ViewSpec::Kind::sweep) {
                builder.add({true, float((px + 0.5) / view.width), float((py + 0.5) / view.height),
                             sweep_v[0], sweep_v[1], sweep_v[2]},
                            pixel);
              } else if (const Ray r = perspective_ray(camera, px, py, view.width, view.height); r.hit) {
                builder.add(r, pixel);
              }
            }
      builder.end_tile();
    }
  set_pixel_gradients(batch);
  return batch;
}

void set_pixel_gradients(RayBatch& rays) {
  const std::size_t width = std::size_t(rays.image_width), height = std::size_t(rays.image_height);
  check_memory_budget(4.0 * double(width) * double(height), "the pixel grid of a view");
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> ray_at(width * height, kNone);  // the ray of each pixel
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    if (rays.origin[i] >= width * height) throw std::logic_error("a ray's pixel lies outside its view's grid");
    ray_at[rays.origin[i]] = std::uint32_t(i);
  }
  // T's change to the next pixel along one axis (step: 1 pixel in x, or a row in y) at pixel p,
  // its coordinate c along that axis of n pixels: towards the quad partner, else the other side.
  const auto gradient = [&](std::size_t p, std::size_t c, std::size_t n, std::size_t step, float& du, float& dv) {
    const std::size_t self = ray_at[p];
    for (const bool up : {c % 2 == 0, c % 2 != 0}) {
      if (up ? c + 1 >= n : c == 0) continue;
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
    gradient(p, x, width, 1, rays.du_dx[i], rays.dv_dx[i]);
    gradient(p, y, height, width, rays.du_dy[i], rays.dv_dy[i]);
  }
}

void check_rays(const RayBatch& rays) {
  const std::size_t n = rays.tx.size();
  for (const auto* a : {&rays.ty, &rays.vx, &rays.vy, &rays.vz, &rays.du_dx, &rays.dv_dx, &rays.du_dy, &rays.dv_dy})
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
    if (std::fabs(tx[i]) > kMaxRayOrigin || std::fabs(ty[i]) > kMaxRayOrigin) throw InputError(ray() + ": |T| beyond 1e6");
    builder.add({true, tx[i], ty[i], float(vx[i] / len), float(vy[i] / len), z}, std::uint32_t(i));
    if ((i + 1) % per_tile == 0) builder.end_tile();
  }
  builder.end_tile();
  return batch;
}

}  // namespace heightmarch
