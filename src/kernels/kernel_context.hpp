#pragma once
// What every technique kernel works with: one packet of rays, the sampler that counts the
// samples it takes, and the layer count of docs/techniques.md.
#include "kernels/packet_sampler.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W>
struct RayPacket {
  vfloat<W> tx, ty, vx, vy, vz;
};

// An output's packet: floats as vfloat<W>, counts and flags as vint<W>.
template <class T, int W>
struct ChannelPacket {
  using type = vint<W>;
};
template <int W>
struct ChannelPacket<float, W> {
  using type = vfloat<W>;
};

// The result of a technique for one packet: every output of the list (heightmarch/hits.hpp), each
// at its initial value until the kernel (or the packet loop) sets it.
template <int W>
struct HitPacket {
#define HEIGHTMARCH_HIT_PACKET(name, element, initial, ...) \
  typename ChannelPacket<element, W>::type name = typename ChannelPacket<element, W>::type(initial);
  HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_PACKET)
#undef HEIGHTMARCH_HIT_PACKET
};

template <int W, Addressing ADDRESSING, Taps TAPS = Taps::memory, Filter FILTER = Filter::bilinear>
class KernelContext {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;

  KernelContext(const KernelTexture& texture, const KernelParams& params, KernelCounters& counters)
      : params(params), texture(texture), sampler_(texture), counters_(counters) {}

  // One height sample, counted for the active lanes in `samples`. Every lane is gathered (all
  // indices are valid): a gather masked by the last comparison would wait for it.
  F sample(F u, F v, B active, I& samples) {
    count(active, samples, 1);
    return sampler_(u, v);
  }

  // One read, not counted: its caller counts it (count_lanes, count_packet_reads).
  F read(F u, F v) const { return sampler_(u, v); }
  // The same read of another texture of the depth map's layout (the cone map's ratios).
  F read(const float* texels, F u, F v) const { return sampler_(texels, u, v); }

  // Trilinear: the levels of the packet's rays, from their gradients, before its first sample.
  void set_footprint(F du_dx, F dv_dx, F du_dy, F dv_dy) {
    sampler_.set_footprint(du_dx, dv_dx, du_dy, dv_dy);
  }

  // Counts n texel reads for the active lanes, for kernels that read texels themselves.
  // `samples` must be the lane counts the kernel returns in HitPacket::samples: the packet loop
  // (src/isa/kernel_table.hpp) sums them into lane_samples once per packet, not here at every read.
  void count(B active, I& samples, int n) {
    count_lanes(active, samples, n);
    count_packet_reads(n);
  }
  // The two halves of count(): n samples for the active lanes, and n reads of the whole packet
  // (the work done, whether or not a lane wanted it).
  static void count_lanes(B active, I& samples, int n) { samples = select(active, samples + I(n), samples); }
  void count_packet_reads(int n) { counters_.packet_samples += std::uint64_t(n) * W; }

  // The tutorial's layer count (heightmarch::layer_count, technique.hpp).
  F layer_count(F cos_theta) const {
    return heightmarch::layer_count(params.min_layers, params.max_layers, cos_theta);
  }

  // Loop bound of docs/techniques.md: at most ceil(N) + 1 layer steps.
  static I step_bound(F layers) { return to_int(ceil(layers)) + I(1); }
  int max_step_bound() const { return int(params.max_layers) + 2; }

  const KernelParams& params;
  const KernelTexture& texture;

 private:
  PacketSampler<W, ADDRESSING, TAPS, FILTER> sampler_;
  KernelCounters& counters_;
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
