#include "baselines/naive_port.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <glm/glm.hpp>

#include "baselines/highway_port.hpp"
#include "heightmarch/error.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {
namespace {

struct Texture {
  const DepthMap& map;

  float fetch(int i, int j) const {
    i %= map.width;
    j %= map.height;
    return map.at(i < 0 ? i + map.width : i, j < 0 ? j + map.height : j);
  }

  // texture(depthMap, uv).r with GL_LINEAR and GL_REPEAT.
  float operator()(glm::vec2 uv) const {
    const glm::vec2 x = uv * glm::vec2(map.width, map.height) - 0.5f;
    const glm::vec2 x0 = glm::floor(x);
    const glm::vec2 f = x - x0;
    const int i = int(x0.x), j = int(x0.y);
    return glm::mix(glm::mix(fetch(i, j), fetch(i + 1, j), f.x),
                    glm::mix(fetch(i, j + 1), fetch(i + 1, j + 1), f.x), f.y);
  }
};

// LearnOpenGL's ParallaxMapping() for POM, as the tutorial writes it, with its sample count.
glm::vec2 parallax_mapping(const Texture& depthMap, glm::vec2 texCoords, glm::vec3 viewDir, float minLayers,
                           float maxLayers, float height_scale, unsigned& samples) {
  const float numLayers =
      glm::mix(maxLayers, minLayers, glm::abs(glm::dot(glm::vec3(0.0, 0.0, 1.0), viewDir)));
  float layerDepth = 1.0f / numLayers;
  float currentLayerDepth = 0.0f;
  glm::vec2 P = glm::vec2(viewDir.x, viewDir.y) / viewDir.z * height_scale;
  glm::vec2 deltaTexCoords = P / numLayers;
  glm::vec2 currentTexCoords = texCoords;
  float currentDepthMapValue = depthMap(currentTexCoords);
  samples = 1;
  // The tutorial's loop is unbounded; its bound here is ceil(N) + 1 steps (docs/techniques.md).
  const int bound = int(std::ceil(numLayers)) + 1;
  for (int step = 0; currentLayerDepth < currentDepthMapValue && step < bound; ++step) {
    currentTexCoords -= deltaTexCoords;
    currentDepthMapValue = depthMap(currentTexCoords);
    currentLayerDepth += layerDepth;
    ++samples;
  }
  glm::vec2 prevTexCoords = currentTexCoords + deltaTexCoords;
  float afterDepth = currentDepthMapValue - currentLayerDepth;
  float beforeDepth = depthMap(prevTexCoords) - currentLayerDepth + layerDepth;
  ++samples;
  float weight = afterDepth / (afterDepth - beforeDepth);
  return prevTexCoords * weight + currentTexCoords * (1.0f - weight);
}

}  // namespace

void naive_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
               HitBuffers& hits) {
  hits.resize(rays.size());
  const Texture texture{map};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1), [&](const auto& tiles) {
    for (std::size_t t = tiles.begin(); t != tiles.end(); ++t)
      for (std::size_t i = rays.tile_offsets[t]; i < rays.tile_offsets[t + 1]; ++i) {
        const glm::vec2 uv =
            parallax_mapping(texture, {rays.tx[i], rays.ty[i]}, {rays.vx[i], rays.vy[i], rays.vz[i]},
                             min_layers, max_layers, scale, hits.samples[i]);
        hits.u[i] = uv.x;
        hits.v[i] = uv.y;
      }
  });
}

namespace {

// A port's kernel over the batch's tiles, on the plain REPEAT depth map; its samples are read
// from hits.samples, as the naive port's.
void trace_port(TraceRangeFn kernel, const DepthMap& map, const RayBatch& rays, float min_layers,
                float max_layers, float scale, HitBuffers& hits) {
  const KernelTexture texture{map.texels.data(), map.width, map.height, map.width, Wrap::repeat};
  trace_tiles(kernel, texture, KernelParams{min_layers, max_layers, 0, scale, false, {0.0f, 0.0f, 1.0f}},
              rays, hits);
}

}  // namespace

void trace_tiles(TraceRangeFn kernel, const KernelTexture& texture, const KernelParams& params,
                 const RayBatch& rays, HitBuffers& hits) {
  hits.resize(rays.size());
  const KernelRays kernel_rays{rays.tx.data(), rays.ty.data(), rays.vx.data(), rays.vy.data(),
                               rays.vz.data()};
  const KernelHits out = kernel_hits(hits);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.tile_count(), 1), [&](const auto& tiles) {
    KernelCounters counters;
    for (std::size_t t = tiles.begin(); t != tiles.end(); ++t)
      kernel(texture, params, kernel_rays, out, rays.tile_offsets[t], rays.tile_offsets[t + 1], counters);
  });
}

void autovec_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
                 Isa isa, HitBuffers& hits) {
  check_cpu_supports(isa, "the auto-vectorised port");
  trace_port(kernel_table(isa).autovec_pom, map, rays, min_layers, max_layers, scale, hits);
}

#ifndef HEIGHTMARCH_HAVE_HIGHWAY
// Built without Google Highway (libhwy-dev): the port runs nowhere.
TraceRangeFn highway_kernel(Isa) { return nullptr; }
#endif

bool highway_port_runs(Isa isa) { return highway_kernel(isa) != nullptr; }

void highway_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
                 Isa isa, HitBuffers& hits) {
  const TraceRangeFn kernel = highway_kernel(isa);
  if (!kernel)
    throw InputError("the Highway port does not run at ISA " + to_string(isa) + " in this build on this CPU");
  trace_port(kernel, map, rays, min_layers, max_layers, scale, hits);
}

}  // namespace heightmarch
