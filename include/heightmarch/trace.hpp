#pragma once
// Traces a ray batch with a technique: packet kernels of one ISA over TBB tile batches.
#include <cstdint>
#include <memory>

#include "heightmarch/exact.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

struct TraceStats {
  std::uint64_t samples = 0;         // height samples of real rays (padding excluded)
  std::uint64_t lane_samples = 0;    // lanes that sampled, padding included
  std::uint64_t packet_samples = 0;  // packet samples x packet width
  double simd_utilization() const {
    return packet_samples ? double(lane_samples) / double(packet_samples) : 1.0;
  }
};

// Holds what a technique needs besides the rays (the padded sampler texture, or the exact
// intersector) so that repeated runs, e.g. in benchmarks, time only the tracing.
class Tracer {
 public:
  Tracer(const DepthMap& map, const TechniqueParams& params, Isa isa);

  // Traces every ray of the batch (padding too) into hits, in parallel over tiles in the
  // current TBB arena. The output does not depend on the thread count or the tile order.
  TraceStats run(const RayBatch& rays, HitBuffers& hits) const;

  // Benchmarks only: the sampler alone at the positions of a march of max_layers steps,
  // all lanes active, no control flow (the samples/s ceiling). hits.depth gets sums.
  TraceStats run_sampler_roofline(const RayBatch& rays, HitBuffers& hits) const;

  const TechniqueParams& params() const { return params_; }
  Isa isa() const { return isa_; }

 private:
  TraceStats run_kernels(const RayBatch& rays, HitBuffers& hits, bool roofline) const;

  const DepthMap* map_;
  TechniqueParams params_;
  Isa isa_;
  SamplerTexture texture_;
  std::unique_ptr<ExactIntersector> exact_;
};

// Limits TBB's worker threads while alive; threads <= 0 means all cores.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  int threads() const { return threads_; }

 private:
  int threads_;
  std::unique_ptr<struct ThreadLimitState> state_;
};

}  // namespace heightmarch
