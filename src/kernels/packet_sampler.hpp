#pragma once
// The bilinear sampler of SPEC section 1 on packets, written once for every width.
// Bit-identical to sample_depth() for texel coordinates below 2^23: the wrap is done in float
// (x - W floor(x / W), then one correction each way) before conversion, so coordinates of any
// size stay finite and every index stays inside the texture, masked lane or not.
#include "kernels/kernel_abi.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W, Wrap WRAP>
class PacketSampler {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;

  explicit PacketSampler(const KernelTexture& t)
      : texels_(t.texels), stride_(t.stride), width_(float(t.width)), height_(float(t.height)),
        inv_width_(1.0f / float(t.width)), inv_height_(1.0f / float(t.height)),
        last_x_(t.width - 1), last_y_(t.height - 1) {}

  F operator()(F u, F v, B active) const {
    F fx, fy;
    const I ix = texel_coordinate(u, width_, inv_width_, last_x_, fx);
    const I iy = texel_coordinate(v, height_, inv_height_, last_y_, fy);
    const I index = iy * I(stride_) + ix;
    const F t00 = gather(texels_, index, active);
    const F t10 = gather(texels_, index + I(1), active);
    const F t01 = gather(texels_, index + I(stride_), active);
    const F t11 = gather(texels_, index + I(stride_ + 1), active);
    const F top = t00 + fx * (t10 - t00);
    const F bottom = t01 + fx * (t11 - t01);
    return top + fy * (bottom - top);
  }

 private:
  // Left tap index along one axis, and the blend weight of the right tap.
  static I texel_coordinate(F uv, F size, F inv_size, std::int32_t last, F& weight) {
    F x = uv * size - F(0.5f);
    if constexpr (WRAP == Wrap::repeat) {
      x = x - size * floor(x * inv_size);
      x = select(x < F(0.0f), x + size, x);
      x = select(x >= size, x - size, x);
    } else {
      // Clamping x itself gives the clamped taps' blend exactly: a + 0 (b - a) = a.
      x = min(max(x, F(0.0f)), size - F(1.0f));
    }
    const F x0 = floor(x);
    weight = x - x0;
    return min(max(to_int(x0), I(0)), I(last));
  }

  const float* texels_;
  std::int32_t stride_;
  F width_, height_, inv_width_, inv_height_;
  std::int32_t last_x_, last_y_;
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
