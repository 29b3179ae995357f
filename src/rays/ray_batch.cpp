#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/rays.hpp"
#include "rays/batch_builder.hpp"

namespace heightmarch {
namespace {

constexpr double kMinViewZ = 5e-7;     // V.z below this is a grazing ray: rejected
constexpr float kMaxRayOrigin = 1e6f;  // |T.x|, |T.y|

}  // namespace

void set_pixel_gradients(RayBatch& rays, int frame_width, int frame_height) {
  rays.frame_width = frame_width;
  rays.frame_height = frame_height;
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

std::string ray_fault(const RayBatch& rays, std::size_t i) {
  const auto within = [](float x) { return std::isfinite(x) && std::fabs(x) <= kMaxRayOrigin; };
  if (!within(rays.tx[i]) || !within(rays.ty[i]))
    return std::isfinite(rays.tx[i]) && std::isfinite(rays.ty[i]) ? "its entry point T is beyond 1e6"
                                                                  : "its entry point T is not finite";
  if (!std::isfinite(rays.vx[i]) || !std::isfinite(rays.vy[i]) || !std::isfinite(rays.vz[i]))
    return "its view vector V is not finite";
  if (!(rays.vz[i] > 0.0f)) return "its view vector has V.z <= 0";
  if (!within(rays.du_dx[i]) || !within(rays.dv_dx[i]) || !within(rays.du_dy[i]) || !within(rays.dv_dy[i]))
    return "its pixel footprint (the gradients of T) is not finite or beyond 1e6";
  return "";
}

void check_rays(const RayBatch& rays) {
  const std::size_t n = rays.tx.size();
  for (const auto* a :
       {&rays.ty, &rays.vx, &rays.vy, &rays.vz, &rays.du_dx, &rays.dv_dx, &rays.du_dy, &rays.dv_dy})
    if (a->size() != n) throw InputError("a ray batch whose arrays differ in length");
  for (std::size_t i = 0; i < n; ++i)
    if (const std::string fault = ray_fault(rays, i); !fault.empty())
      throw InputError("ray " + std::to_string(i + 1) + " of the batch: " + fault);
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
