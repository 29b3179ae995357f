#pragma once
// The loop over packets of one ISA: loads W rays, runs the technique, stores the hits.
// Included once per ISA by src/isa/kernels_<isa>.cpp inside its own namespace.
#include "kernels/parallax.hpp"
#include "kernels/pom.hpp"
#include "kernels/relief.hpp"
#include "kernels/roofline.hpp"
#include "kernels/shadow.hpp"
#include "kernels/steep.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Addressing ADDRESSING, class Technique>
void trace_packets(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                   const KernelHits& hits, std::size_t begin, std::size_t end,
                   KernelCounters& counters, Technique technique) {
  using F = vfloat<W>;
  KernelCounters local;  // in registers, not behind the output pointers (char aliases all)
  KernelContext<W, ADDRESSING> context(texture, params, local);
  for (std::size_t i = begin; i < end; i += W) {
    const RayPacket<W> ray{F::load(rays.tx + i), F::load(rays.ty + i), F::load(rays.vx + i),
                           F::load(rays.vy + i), F::load(rays.vz + i)};
    const HitPacket<W> hit = technique(context, ray);
    hit.u.store(hits.u + i);
    hit.v.store(hits.v + i);
    hit.depth.store(hits.depth + i);
    hit.shadow.store(hits.shadow + i);
    hit.samples.store(reinterpret_cast<std::int32_t*>(hits.samples + i));
    const auto outside = (hit.u < F(0.0f)) | (hit.u > F(1.0f)) | (hit.v < F(0.0f)) | (hit.v > F(1.0f));
    const vint<W> flags = select(outside, vint<W>(params.discard ? 1 : 0), vint<W>(0));
    alignas(64) std::int32_t lanes[W];
    flags.store(lanes);
    for (int lane = 0; lane < W; ++lane) hits.discarded[i + lane] = std::uint8_t(lanes[lane]);
  }
  counters.lane_samples += local.lane_samples;
  counters.packet_samples += local.packet_samples;
}

template <int W, Addressing ADDRESSING>
void trace_range_addressing(const KernelTexture& texture, const KernelParams& params,
                      const KernelRays& rays, const KernelHits& hits, std::size_t begin,
                      std::size_t end, KernelCounters& counters) {
  auto run = [&](auto technique) {
    trace_packets<W, ADDRESSING>(texture, params, rays, hits, begin, end, counters, technique);
  };
  using K = KernelContext<W, ADDRESSING>;
  using R = RayPacket<W>;
  if (params.sampler_roofline) return run([](K& k, const R& r) { return sampler_roofline(k, r); });
  switch (params.technique) {
    case Technique::parallax: run([](K& k, const R& r) { return parallax<false>(k, r); }); break;
    case Technique::parallax_limited: run([](K& k, const R& r) { return parallax<true>(k, r); }); break;
    case Technique::steep: run([](K& k, const R& r) { return steep<false>(k, r); }); break;
    case Technique::steep_limited: run([](K& k, const R& r) { return steep<true>(k, r); }); break;
    case Technique::relief: run([](K& k, const R& r) { return relief(k, r); }); break;
    case Technique::pom: run([](K& k, const R& r) { return pom(k, r); }); break;
    case Technique::shadow: run([](K& k, const R& r) { return shadow(k, r); }); break;
    case Technique::exact: break;  // not a packet kernel: see ExactIntersector
  }
}

template <int W>
void trace_range_packets(const KernelTexture& texture, const KernelParams& params,
                         const KernelRays& rays, const KernelHits& hits, std::size_t begin,
                         std::size_t end, KernelCounters& counters) {
  switch (addressing_of(texture)) {
    case Addressing::repeat_pow2:
      return trace_range_addressing<W, Addressing::repeat_pow2>(texture, params, rays, hits, begin, end, counters);
    case Addressing::repeat:
      return trace_range_addressing<W, Addressing::repeat>(texture, params, rays, hits, begin, end, counters);
    case Addressing::clamp:
      return trace_range_addressing<W, Addressing::clamp>(texture, params, rays, hits, begin, end, counters);
  }
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
