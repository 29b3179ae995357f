#pragma once
// A few rays over the builtin `flat` heightfield (depth 0.5 everywhere), whose exact hit is
// T - 0.5 s V.xy / V.z, and a check of a technique's hits against it.
#include <cmath>
#include <cstdio>
#include <heightmarch/heightfield.hpp>
#include <heightmarch/hits.hpp>
#include <heightmarch/rays.hpp>
#include <heightmarch/technique.hpp>

inline heightmarch::RayBatch flat_rays() {
  const float s = std::sqrt(0.5f);  // 45 degrees from the normal
  return heightmarch::make_ray_list({0.5f, 0.25f, 0.75f, 0.5f}, {0.5f, 0.5f, 0.25f, 0.75f},
                                    {0.0f, s, 0.0f, -0.6f}, {s, 0.0f, -s, 0.0f}, {s, s, s, 0.8f});
}

// Prints each hit; returns 0 when every hit is within 1e-3 of the exact one.
inline int check_flat_hits(const char* who, const heightmarch::RayBatch& rays,
                           const heightmarch::HitBuffers& hits, float scale) {
  int bad = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    const float u = rays.tx[i] - 0.5f * scale * rays.vx[i] / rays.vz[i];
    const float v = rays.ty[i] - 0.5f * scale * rays.vy[i] / rays.vz[i];
    const bool ok = std::abs(hits.u[i] - u) < 1e-3f && std::abs(hits.v[i] - v) < 1e-3f &&
                    std::abs(hits.depth[i] - 0.5f) < 1e-3f;
    std::printf("%s: ray %u hit uv (%.4f, %.4f) depth %.4f, exact (%.4f, %.4f) depth 0.5000%s\n", who,
                rays.origin[i], hits.u[i], hits.v[i], hits.depth[i], u, v, ok ? "" : "  WRONG");
    bad += !ok;
  }
  return bad == 0 ? 0 : 1;
}
