#pragma once
// The naive POM port (naive_port.cpp) as a user would vectorise it with the compiler alone: the
// same lines and the same arithmetic, over arrays of rays, one `#pragma omp simd` loop per layer
// step, the tutorial's loop condition turned into a per-ray flag and its branches into selects.
// No packet types, no intrinsics: what -O3 makes of it with this ISA's flags (cmake/isa_list.cmake:
// -fopenmp-simd, and -fno-trapping-math, without which GCC 12 if-converts nothing; neither
// changes a result). GCC 12 vectorised these loops only with their reduction clauses (the
// flag of rays still going, the samples taken), checked with -fopt-info-vec. Included once per
// ISA by its generated translation unit (src/isa/autovec.cpp.in).
#include <algorithm>
#include <cmath>

#include "kernels/kernel_abi.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {
namespace autovec {

// Rays marched together: enough for a few vectors of any width, little wasted when rays of a
// block stop at different layers.
inline constexpr int kBlock = 64;

// GL_REPEAT of a texel index, i mod n, without the integer division that does not vectorise.
inline int wrap(int i, int n, float inv_n) {
  int r = i - n * int(std::floor(float(i) * inv_n));
  r = r < 0 ? r + n : r;
  return r >= n ? r - n : r;
}

inline float mix(float x, float y, float a) { return x * (1.0f - a) + y * a; }  // glm::mix

// texture(depthMap, uv).r with GL_LINEAR and GL_REPEAT, as naive_port.cpp's Texture.
inline float sample(const KernelTexture& t, float u, float v) {
  const float x = u * float(t.width) - 0.5f, y = v * float(t.height) - 0.5f;
  const float x0 = std::floor(x), y0 = std::floor(y);
  const float fx = x - x0, fy = y - y0;
  const float inv_w = 1.0f / float(t.width), inv_h = 1.0f / float(t.height);
  const int i0 = wrap(int(x0), t.width, inv_w), i1 = wrap(int(x0) + 1, t.width, inv_w);
  const int j0 = wrap(int(y0), t.height, inv_h), j1 = wrap(int(y0) + 1, t.height, inv_h);
  const float* row0 = t.texels + j0 * t.stride;
  const float* row1 = t.texels + j1 * t.stride;
  return mix(mix(row0[i0], row0[i1], fx), mix(row1[i0], row1[i1], fx), fy);
}

}  // namespace autovec

// Traces rays [begin, end) of a DepthMap laid out plainly (stride = width, REPEAT); writes u, v
// and samples as the naive port does (depth and shadow are not the port's). Not inline: this is
// the ISA's one definition, declared in kernel_abi.hpp.
void autovec_pom(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                 const KernelHits& hits, std::size_t begin, std::size_t end, KernelCounters& counters) {
  using namespace autovec;
  const float min_layers = params.min_layers, max_layers = params.max_layers, height_scale = params.scale;
  for (std::size_t first = begin; first < end; first += kBlock) {
    const int n = int(std::min<std::size_t>(kBlock, end - first));
    const float *tx = rays.tx + first, *ty = rays.ty + first;
    const float *vx = rays.vx + first, *vy = rays.vy + first, *vz = rays.vz + first;
    float *hit_u = hits.u + first, *hit_v = hits.v + first;
    std::uint32_t* hit_samples = hits.samples + first;
    float u[kBlock], v[kBlock], du[kBlock], dv[kBlock], layer_depth[kBlock], current_layer_depth[kBlock];
    float depth_map_value[kBlock];
    int bound[kBlock], going[kBlock];
    unsigned samples[kBlock];
    int any = 0;
#pragma omp simd reduction(| : any)
    for (int k = 0; k < n; ++k) {
      const float num_layers = mix(max_layers, min_layers, std::fabs(vz[k]));  // |dot((0, 0, 1), V)|
      layer_depth[k] = 1.0f / num_layers;
      current_layer_depth[k] = 0.0f;
      du[k] = vx[k] / vz[k] * height_scale / num_layers;
      dv[k] = vy[k] / vz[k] * height_scale / num_layers;
      u[k] = tx[k];
      v[k] = ty[k];
      depth_map_value[k] = sample(texture, u[k], v[k]);
      samples[k] = 1;
      bound[k] = int(std::ceil(num_layers)) + 1;
      going[k] = (current_layer_depth[k] < depth_map_value[k]) & (0 < bound[k]);
      any |= going[k];
    }
    // The tutorial's while loop, one step for every ray of the block at a time.
    for (int step = 1; any; ++step) {
      any = 0;
#pragma omp simd reduction(| : any)
      for (int k = 0; k < n; ++k) {
        const int g = going[k];
        const float next_u = u[k] - du[k], next_v = v[k] - dv[k];
        const float next_value = sample(texture, next_u, next_v);
        const float next_depth = current_layer_depth[k] + layer_depth[k];
        u[k] = g ? next_u : u[k];
        v[k] = g ? next_v : v[k];
        depth_map_value[k] = g ? next_value : depth_map_value[k];
        current_layer_depth[k] = g ? next_depth : current_layer_depth[k];
        samples[k] += unsigned(g);
        going[k] = g & (next_depth < next_value) & (step < bound[k]);
        any |= going[k];
      }
    }
    unsigned taken = 0;
#pragma omp simd reduction(+ : taken)
    for (int k = 0; k < n; ++k) {
      const float prev_u = u[k] + du[k], prev_v = v[k] + dv[k];
      const float after_depth = depth_map_value[k] - current_layer_depth[k];
      const float before_depth = sample(texture, prev_u, prev_v) - current_layer_depth[k] + layer_depth[k];
      const float weight = after_depth / (after_depth - before_depth);
      hit_u[k] = prev_u * weight + u[k] * (1.0f - weight);
      hit_v[k] = prev_v * weight + v[k] * (1.0f - weight);
      hit_samples[k] = samples[k] + 1;
      taken += samples[k] + 1;
    }
    counters.lane_samples += taken;
    counters.packet_samples += taken;
  }
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
