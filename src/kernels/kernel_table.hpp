#pragma once
// One ISA's kernel table: every technique of the registry (technique_list.hpp) x every
// addressing mode, each the packet loop below around the technique's kernel. Included once per
// ISA by src/isa/kernels_<isa>.cpp inside its own namespace.
#include "heightmarch/technique_list.hpp"
#include "kernels/roofline.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The loop over packets: loads W rays, runs the technique, stores the hits.
template <int W, Addressing ADDRESSING, class Kernel>
void trace_packets(const KernelTexture& texture, const KernelParams& params, const KernelRays& rays,
                   const KernelHits& hits, std::size_t begin, std::size_t end,
                   KernelCounters& counters) {
  using F = vfloat<W>;
  KernelCounters local;  // in registers, not behind the output pointers (char aliases all)
  KernelContext<W, ADDRESSING> context(texture, params, local);
  const Kernel kernel;
  for (std::size_t i = begin; i < end; i += W) {
    const RayPacket<W> ray{F::load(rays.tx + i), F::load(rays.ty + i), F::load(rays.vx + i),
                           F::load(rays.vy + i), F::load(rays.vz + i)};
    const HitPacket<W> hit = kernel(context, ray);
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

// Each registry row's CPU call as a kernel type.
#define HEIGHTMARCH_TECHNIQUE_KERNEL(id, name, layered, refine, cpu_call, ...) \
  struct Kernel_##id {                                                         \
    template <class Context, class Ray>                                        \
    auto operator()(Context& k, const Ray& ray) const {                        \
      return cpu_call;                                                         \
    }                                                                          \
  };
HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_KERNEL)
#undef HEIGHTMARCH_TECHNIQUE_KERNEL

struct Kernel_sampler_roofline {
  template <class Context, class Ray>
  auto operator()(Context& k, const Ray& ray) const {
    return sampler_roofline(k, ray);
  }
};

// The addressing modes in Addressing's order.
template <int W, class Kernel>
constexpr void fill_addressing(TraceRangeFn (&row)[kAddressingCount]) {
  row[int(Addressing::repeat_pow2)] = &trace_packets<W, Addressing::repeat_pow2, Kernel>;
  row[int(Addressing::repeat)] = &trace_packets<W, Addressing::repeat, Kernel>;
  row[int(Addressing::clamp)] = &trace_packets<W, Addressing::clamp, Kernel>;
}

template <int W>
constexpr KernelTable make_kernel_table() {
  KernelTable table{};
  table.packet_width = W;
#define HEIGHTMARCH_TECHNIQUE_ROW(id, ...) \
  fill_addressing<W, Kernel_##id>(table.technique[int(Technique::id)]);
  HEIGHTMARCH_TECHNIQUES(HEIGHTMARCH_TECHNIQUE_ROW)
#undef HEIGHTMARCH_TECHNIQUE_ROW
  fill_addressing<W, Kernel_sampler_roofline>(table.sampler_roofline);
  return table;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
