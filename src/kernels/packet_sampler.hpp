#pragma once
// The bilinear sampler of docs/conventions.md on packets, written once for every width.
// Bit-identical to sample_depth() for texel coordinates below 2^23. Wrapping happens before
// integer conversion or with a mask, so coordinates of any size stay finite and every index
// stays inside the texture, masked lane or not.
#include "kernels/kernel_abi.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// Where the taps come from: the texture, or registers holding 1.0 (the compute ceiling: the same
// arithmetic with no memory access; every sample reads depth 1, so every ray marches to its bound).
enum class Taps { memory, registers };

template <int W, Addressing ADDRESSING, Taps TAPS = Taps::memory>
class PacketSampler {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;

  explicit PacketSampler(const KernelTexture& t)
      : texels_(t.texels), stride_(t.stride), rows_(t.height + 1), width_(float(t.width)), height_(float(t.height)),
        inv_width_(1.0f / float(t.width)), inv_height_(1.0f / float(t.height)),
        last_x_(t.width - 1), last_y_(t.height - 1) {}

  F operator()(F u, F v) const {
    F fx, fy;
    const I ix = texel_coordinate(u, width_, inv_width_, last_x_, fx);
    const I iy = texel_coordinate(v, height_, inv_height_, last_y_, fy);
    F t00, t10, t01, t11;
    if constexpr (TAPS == Taps::memory) {
      fetch_taps(texels_, stride_, rows_, ix, iy, t00, t10, t01, t11);
    } else {
      const I index = iy * I(stride_) + ix;
      t00 = t10 = t01 = t11 = F(1.0f);
      register_pairs(index, t00, t10);
      register_pairs(index, t01, t11);
    }
    const F top = t00 + fx * (t10 - t00);
    const F bottom = t01 + fx * (t11 - t01);
    return top + fy * (bottom - top);
  }

 private:
  // Left tap index along one axis, and the blend weight of the right tap.
  static I texel_coordinate(F uv, F size, F inv_size, std::int32_t last, F& weight) {
    const F x = uv * size - F(0.5f);
    if constexpr (ADDRESSING == Addressing::clamp) {
      // Clamping x itself gives the clamped taps' blend exactly: a + 0 (b - a) = a.
      const F clamped = min(max(x, F(0.0f)), size - F(1.0f));
      const F x0 = floor(clamped);
      weight = clamped - x0;
      return to_int(x0);
    } else {
      const F x0 = floor(x);
      weight = x - x0;
      if constexpr (ADDRESSING == Addressing::repeat_pow2) {
        return to_int(x0) & I(last);  // out of int range converts to INT32_MIN: index 0
      } else {
        // floor(x) wrapped into [0, size) in float: integer-valued, exact below 2^24.
        F i = x0 - size * floor(x0 * inv_size);
        i = select(i < F(0.0f), i + size, i);
        i = select(i >= size, i - size, i);
        return min(max(to_int(i), I(0)), I(last));
      }
    }
  }

  const float* texels_;
  std::int32_t stride_, rows_;
  F width_, height_, inv_width_, inv_height_;
  std::int32_t last_x_, last_y_;
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
