#include "glsl/screen_layout.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include "heightmarch/memory_budget.hpp"

namespace heightmarch {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

// The drawn arrays of `texels` texels, each a texel no quad needs: straight down at the map's
// centre, as the draw's first texel would cost least.
void size_drawn(DrawnRays& d, std::size_t texels) {
  check_memory_budget(48.0 * double(texels), "the GLSL layout of " + std::to_string(texels) + " texels");
  RayBatch& r = d.rays;
  for (auto* a : {&r.tx, &r.ty}) a->assign(texels, 0.5f);
  for (auto* a : {&r.vx, &r.vy, &r.du_dx, &r.dv_dx, &r.du_dy, &r.dv_dy}) a->assign(texels, 0.0f);
  r.vz.assign(texels, 1.0f);
  d.turn_u.assign(texels, 0.0f);
  d.turn_v.assign(texels, 0.0f);
  d.drawn.assign(texels, 0);
}

void copy_ray(const RayBatch& from, std::size_t i, DrawnRays& to, std::size_t t) {
  RayBatch& r = to.rays;
  r.tx[t] = from.tx[i];
  r.ty[t] = from.ty[i];
  r.vx[t] = from.vx[i];
  r.vy[t] = from.vy[i];
  r.vz[t] = from.vz[i];
  r.du_dx[t] = from.du_dx[i];
  r.dv_dx[t] = from.dv_dx[i];
  r.du_dy[t] = from.du_dy[i];
  r.dv_dy[t] = from.dv_dy[i];
  to.drawn[t] = 1;
}

// Rows of kRowWidth in batch order: the layout of a batch without a pixel grid.
ScreenLayout in_rows(const RayBatch& rays) {
  ScreenLayout layout;
  const std::size_t n = rays.size();
  size_drawn(layout.drawn, (n + kRowWidth - 1) / kRowWidth * kRowWidth);
  layout.drawn.row_width = kRowWidth;
  layout.texel_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    copy_ray(rays, i, layout.drawn, i);
    layout.texel_of[i] = std::uint32_t(i);
  }
  return layout;
}

}  // namespace

ScreenLayout screen_layout(const RayBatch& rays) {
  const int fw = rays.frame_width, fh = rays.frame_height;
  if (fw <= 0 || fh <= 0) return in_rows(rays);
  if (rays.image_width % fw != 0 || rays.image_height % fh != 0)
    throw std::logic_error("a batch whose image is no whole number of frames");
  // Each frame at even offsets: GL's quads are aligned to even window coordinates.
  const int cols = rays.image_width / fw, rows = rays.image_height / fh;
  const int even_w = fw + fw % 2, even_h = fh + fh % 2;
  const std::size_t width = std::size_t(cols) * std::size_t(even_w),
                    height = std::size_t(rows) * std::size_t(even_h);
  ScreenLayout layout;
  layout.screen = true;
  DrawnRays& d = layout.drawn;
  size_drawn(d, width * height);
  d.row_width = std::uint32_t(width);
  std::vector<std::uint32_t> ray_at(width * height, kNone);
  layout.texel_of.resize(rays.size());
  const std::size_t image_width = std::size_t(rays.image_width);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) {  // a copy of its tile's last ray
      layout.texel_of[i] = layout.texel_of[i - 1];
      continue;
    }
    const std::size_t x = rays.origin[i] % image_width, y = rays.origin[i] / image_width;
    const std::size_t t = (y / std::size_t(fh) * std::size_t(even_h) + y % std::size_t(fh)) * width +
                          x / std::size_t(fw) * std::size_t(even_w) + x % std::size_t(fw);
    layout.texel_of[i] = std::uint32_t(t);
    ray_at[t] = std::uint32_t(i);
    copy_ray(rays, i, d, t);
  }
  // Quad by quad: its rays' T made continuous with its first ray's by whole turns, and each texel
  // without a ray continued from a neighbour that has one (its partner across x, else across y,
  // else across the diagonal) by that neighbour's gradients.
  for (std::size_t qy = 0; qy < height; qy += 2)
    for (std::size_t qx = 0; qx < width; qx += 2) {
      const std::array<std::size_t, 4> quad = {qy * width + qx, qy * width + qx + 1, (qy + 1) * width + qx,
                                               (qy + 1) * width + qx + 1};
      std::size_t first = 4;
      for (std::size_t k = 0; k < 4 && first == 4; ++k)
        if (ray_at[quad[k]] != kNone) first = k;
      if (first == 4) continue;
      for (std::size_t k = 0; k < 4; ++k) {
        if (ray_at[quad[k]] == kNone) continue;
        d.turn_u[quad[k]] = std::round(d.rays.tx[quad[first]] - d.rays.tx[quad[k]]);
        d.turn_v[quad[k]] = std::round(d.rays.ty[quad[first]] - d.rays.ty[quad[k]]);
      }
      for (std::size_t k = 0; k < 4; ++k) {
        if (ray_at[quad[k]] != kNone) continue;
        std::size_t from = k ^ 1;  // k's bits: x, then y
        if (ray_at[quad[from]] == kNone) from = k ^ 2;
        if (ray_at[quad[from]] == kNone) from = k ^ 3;
        const std::size_t s = quad[from], t = quad[k];
        const float dx = float(int(k & 1) - int(from & 1)), dy = float(int(k >> 1) - int(from >> 1));
        copy_ray(d.rays, s, d, t);
        d.rays.tx[t] = d.rays.tx[s] + dx * d.rays.du_dx[s] + dy * d.rays.du_dy[s];
        d.rays.ty[t] = d.rays.ty[s] + dx * d.rays.dv_dx[s] + dy * d.rays.dv_dy[s];
        d.turn_u[t] = d.turn_u[s];
        d.turn_v[t] = d.turn_v[s];
      }
    }
  return layout;
}

}  // namespace heightmarch
