#pragma once
// What the configurations of one heightfield and view share in the measurement pass: the ray
// batch, the exact hits per set of parameters and the scalar references, each computed once; and
// the cache of depth maps and scenes they come from.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "experiment/configuration.hpp"
#include "heightmarch/exact.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/tracer.hpp"

namespace heightmarch {

class Scene {
 public:
  Scene(const DepthMap& map, const ViewSpec& view);

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

  const DepthMap& map;
  const RayBatch rays;
  HitBuffers scratch;  // hits of timed runs: one buffer, so timings see no page faults

 private:
  std::map<std::string, std::unique_ptr<HitBuffers>> exact_, surface_read_, references_;
};

// Depth maps by source and scenes by heightfield and view, built on first use.
class SceneCache {
 public:
  const DepthMap& depth_map(const HeightfieldSource& source);
  Scene& scene(const Configuration& config);
  void forget_scenes();  // frees every scene but the depth maps

 private:
  std::vector<std::pair<HeightfieldSource, std::unique_ptr<DepthMap>>> maps_;
  std::vector<std::pair<Configuration, std::unique_ptr<Scene>>> scenes_;
};

}  // namespace heightmarch
