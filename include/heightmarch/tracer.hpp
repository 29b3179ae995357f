#pragma once
// Traces a ray batch with a technique: packet kernels of one ISA over TBB tile batches.
#include <cstdint>
#include <memory>

#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/precomputed.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch {

// The plain structs of the dispatch boundary (src/kernels/kernel_abi.hpp).
struct KernelTexture;
struct KernelParams;
struct KernelRays;
struct KernelHits;
struct KernelCounters;

// The lanes' counts of one trace; the samples of its real rays are total_samples() of the hits
// (metrics.hpp), not counted here: a pass over the batch would be part of every timed trace.
struct TraceStats {
  std::uint64_t lane_samples = 0;    // lanes that sampled, padding included
  std::uint64_t packet_samples = 0;  // packet samples x packet width
  double simd_utilization() const {
    return packet_samples ? double(lane_samples) / double(packet_samples) : 1.0;
  }
};

// The packet kernel of one technique on one ISA, chosen once when built (from the ISA's kernel
// table), with the padded sampler texture it reads, so that repeated runs time only the tracing.
class Tracer {
 public:
  // Throws InputError when the CPU lacks the ISA.
  Tracer(const DepthMap& map, const TechniqueParams& params, Isa isa);

  // Traces every ray of the batch (padding too) into hits, in parallel over tiles in the
  // current TBB arena. The output does not depend on the thread count or the tile order.
  TraceStats run(const RayBatch& rays, HitBuffers& hits) const;

  // Benchmarks only: the sampler alone at the positions of a march of max_layers steps,
  // all lanes active, no control flow (the samples/s ceiling). hits.depth gets sums.
  TraceStats run_sampler_roofline(const RayBatch& rays, HitBuffers& hits) const;

  // Benchmarks only: POM's march and bilinear arithmetic on taps held in registers (every
  // sample reads depth 1), no texture access: the compute ceiling of samples/s.
  TraceStats run_compute_ceiling(const RayBatch& rays, HitBuffers& hits) const;

  const TechniqueParams& params() const { return params_; }
  Isa isa() const { return isa_; }
  // What the technique reads besides the depth map (its registry row's needs).
  const PrecomputedTextures& precomputed() const { return precomputed_; }

 private:
  using KernelFn = void (*)(const KernelTexture&, const KernelParams&, const KernelRays&, const KernelHits&,
                            std::size_t, std::size_t, KernelCounters&);
  TraceStats run_kernel(KernelFn kernel, const RayBatch& rays, HitBuffers& hits) const;

  TechniqueParams params_;
  Isa isa_;
  SamplerTexture texture_;  // with its mip chain for a trilinear technique
  PrecomputedTextures precomputed_;
  SamplerTexture cone_ratios_;  // trilinear cone: the ratios with their mip chain
  KernelFn technique_kernel_;
  KernelFn roofline_kernel_;
  KernelFn ceiling_kernel_;
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
