#include "experiment/scene.hpp"

#include <cstdio>

namespace heightmarch {
namespace {

// A key of what changes a run's output among the configurations of one scene.
std::string params_key(const TechniqueParams& p, bool with_technique, bool with_filter) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%d/%g/%g/%d/%a/%d/%d/%d/%a/%a/%a", with_technique ? int(p.technique) : -1,
                p.layers.min_layers, p.layers.max_layers, p.refine_steps(), p.scale, int(p.wrap),
                with_filter ? int(p.filter) : -1, int(p.discard), p.light[0], p.light[1], p.light[2]);
  return buf;
}

// The key of the exact hits: what the exact references read (scale, wrap, discard, the light and,
// for the surface read, the filter), never a technique's search (its layers, its refinement), so
// the rows of a technique x layers grid share them.
std::string exact_key(const TechniqueParams& p, bool with_filter) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%a/%d/%d/%d/%a/%a/%a", p.scale, int(p.wrap),
                with_filter ? int(p.filter) : -1, int(p.discard), p.light[0], p.light[1], p.light[2]);
  return buf;
}

}  // namespace

Scene::Scene(const DepthMap& map, const ViewSpec& view, std::function<const Albedo&()> albedo)
    : map(map), rays(make_view_rays(view)), view_(view), albedo_(std::move(albedo)) {}

Shading Scene::shading(const TechniqueParams& params) {
  Shading s;
  s.map = &map;
  s.albedo = &albedo_();
  s.wrap = params.wrap;
  s.scale = params.scale;
  s.light = {params.light[0], params.light[1], params.light[2]};
  return s;
}

const LinearImage& Scene::supersampled_exact(const TechniqueParams& params, int n) {
  const LightVisibility visibility = visibility_for(params.technique);
  auto& slot = supersampled_[params_key(params, false, false) + "/" + std::to_string(n) +
                             (visibility == LightVisibility::compute ? "/visibility" : "")];
  if (slot) return *slot;
  slot = std::make_unique<LinearImage>();
  const Shading shading = this->shading(params);
  // Subpixel (i, j) of n x n at (i + 0.5) / n - 0.5 of a pixel from its centre: each pass is the
  // view with its rays moved by that much, its footprint 1 / n of a pixel's.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const RayBatch pass =
          make_view_rays(subpixel_view(view_, (i + 0.5f) / float(n) - 0.5f, (j + 0.5f) / float(n) - 0.5f));
      const HitBuffers hits = exact_hits(map, pass, params, visibility);
      accumulate_shaded(shading, pass, hits, 1.0f / float(n), 1.0f / float(n * n), *slot);
    }
  return *slot;
}

const HitBuffers& Scene::exact(const TechniqueParams& params) {
  const LightVisibility visibility = visibility_for(params.technique);
  auto& slot =
      exact_[exact_key(params, false) + (visibility == LightVisibility::compute ? "/visibility" : "")];
  if (!slot) slot = std::make_unique<HitBuffers>(exact_hits(map, rays, params, visibility));
  return *slot;
}

const HitBuffers& Scene::surface_read(const TechniqueParams& params) {
  if (params.filter_read() == Filter::bilinear) return exact(params);
  const HitBuffers& level0 = exact(params);
  auto& slot = surface_read_[exact_key(params, true)];
  if (!slot) {
    slot = std::make_unique<HitBuffers>();
    FilteredExactReference(map, params).run(rays, level0, *slot);
  }
  return *slot;
}

const HitBuffers& Scene::reference(RunKind kind, const TechniqueParams& params, TracerRun run) {
  auto& slot = references_[to_string(kind) + "/" + params_key(params, info(kind).traces_technique, true)];
  if (!slot) {
    slot = std::make_unique<HitBuffers>();
    (Tracer(map, params, Isa::scalar).*run)(rays, *slot);
  }
  return *slot;
}

const DepthMap& SceneCache::depth_map(const HeightfieldSource& source) {
  for (auto& [s, map] : maps_)
    if (s == source) return *map;
  maps_.emplace_back(source, std::make_unique<DepthMap>(load_heightfield(source)));
  return *maps_.back().second;
}

const Albedo& SceneCache::albedo(const HeightfieldSource& source) {
  for (auto& [s, albedo] : albedos_)
    if (s == source) return *albedo;
  albedos_.emplace_back(source,
                        std::make_unique<Albedo>(source.albedo.empty() ? procedural_albedo(depth_map(source))
                                                                       : load_albedo(source.albedo)));
  return *albedos_.back().second;
}

Scene& SceneCache::scene(const Configuration& c) {
  for (auto& [key, scene] : scenes_)
    if (key.heightfield == c.heightfield && key.view == c.view) return *scene;
  const HeightfieldSource source = c.heightfield;
  scenes_.emplace_back(c,
                       std::make_unique<Scene>(depth_map(source), c.view,
                                               [this, source]() -> const Albedo& { return albedo(source); }));
  return *scenes_.back().second;
}

void SceneCache::forget_scenes() { scenes_.clear(); }

}  // namespace heightmarch
