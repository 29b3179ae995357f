#pragma once
// What the configurations of one heightfield and view share in the measurement pass: the ray
// batch, the exact hits per set of parameters and the scalar references, each computed once; and
// the cache of depth maps and scenes they come from.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "experiment/configuration.hpp"
#include "heightmarch/exact.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/tracer.hpp"
#include "io/shading.hpp"

namespace heightmarch {

class Scene {
 public:
  // `albedo` gives the map's colour texture when first asked for (SceneCache::albedo).
  Scene(const DepthMap& map, const ViewSpec& view, std::function<const Albedo&()> albedo);

  // The exact hits for these parameters (with the light's visibility where the technique writes
  // a shadow factor).
  const HitBuffers& exact(const TechniqueParams& params);

  // The exact hits on the surface a technique with these parameters reads
  // (FilteredExactReference): exact(params) itself where that is level 0.
  const HitBuffers& surface_read(const TechniqueParams& params);

  // The scalar reference of a run kind's Tracer run (`run`, one of Tracer's run methods) with
  // these parameters, computed once: what every ISA's output must equal bit for bit.
  using TracerRun = TraceStats (Tracer::*)(const RayBatch&, HitBuffers&) const;
  const HitBuffers& reference(RunKind kind, const TechniqueParams& params, TracerRun run);

  // The exact reference as a player would see it at its best (docs/measures.md#the-shaded-image):
  // n x n subpixel rays per pixel on an ordered grid, each traced exactly (with the light's
  // visibility where the parameters' technique writes a shadow factor) and shaded, resolved as a
  // GPU resolves a multisampled sRGB target, the box average of a pixel's samples in linear light.
  // Computed once per parameters and n, pass by pass (a batch of the view's size each).
  const LinearImage& supersampled_exact(const TechniqueParams& params, int n);

  // How the scene's hits are shaded with these parameters: the map, its colour texture (built on
  // first use), the wrap, scale and light.
  Shading shading(const TechniqueParams& params);

  const DepthMap& map;
  const RayBatch rays;
  HitBuffers scratch;  // hits of timed runs: one buffer, so timings see no page faults

 private:
  const ViewSpec view_;
  std::function<const Albedo&()> albedo_;
  std::map<std::string, std::unique_ptr<HitBuffers>> exact_, surface_read_, references_;
  std::map<std::string, std::unique_ptr<LinearImage>> supersampled_;
};

// Depth maps by source and scenes by heightfield and view, built on first use.
class SceneCache {
 public:
  const DepthMap& depth_map(const HeightfieldSource& source);
  // Its colour texture: the file it names (HeightfieldSource::albedo) or the procedural one of
  // its depth map, built on first use and kept.
  const Albedo& albedo(const HeightfieldSource& source);
  Scene& scene(const Configuration& config);
  void forget_scenes();  // frees every scene but the depth maps

 private:
  std::vector<std::pair<HeightfieldSource, std::unique_ptr<DepthMap>>> maps_;
  std::vector<std::pair<HeightfieldSource, std::unique_ptr<Albedo>>> albedos_;
  std::vector<std::pair<Configuration, std::unique_ptr<Scene>>> scenes_;
};

}  // namespace heightmarch
