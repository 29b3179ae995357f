#pragma once
// The hand-written POM's structure written on Google Highway's ops (highway_structured.cpp): the
// fair outside anchor of the packet kernels, run over a batch as a Tracer runs a technique.
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/sampler.hpp"
#include "heightmarch/technique.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {

// Whether it runs at the ISA: this build has Highway, which compiled the ISA's Highway target
// (cmake/isa_list.cmake), and the CPU runs it.
bool highway_structured_runs(Isa isa);

class HighwayStructuredPom {
 public:
  // POM with these parameters on a REPEAT map of power-of-two sides (the builtins'), at the
  // ISA's Highway target. Throws InputError for anything else or where it does not run.
  HighwayStructuredPom(const DepthMap& map, const TechniqueParams& params, Isa isa);

  // The same hits as Tracer::run of the technique, bit for bit (and its SIMD use: the same march).
  void run(const RayBatch& rays, HitBuffers& hits) const;

 private:
  TechniqueParams params_;
  TraceRangeFn kernel_;
  SamplerTexture texture_;
};

}  // namespace heightmarch
