#pragma once
// The sampler of docs/conventions.md on packets, written once for every width: bilinear on level 0,
// or trilinear over the mip chain at each lane's level of detail. Bit-identical to sample_depth()
// for texel coordinates below 2^23. Wrapping happens before integer conversion or with a mask, so
// coordinates of any size stay finite and every index stays inside the texture, masked lane or not.
#include <type_traits>

#include "heightmarch/mip_chain.hpp"
#include "kernels/kernel_abi.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// Where the taps come from: the texture, or registers holding 1.0 (the compute ceiling: the same
// arithmetic with no memory access; every sample reads depth 1, so every ray marches to its bound).
enum class Taps { memory, registers };

// Trilinear: each level's constants, looked up per lane where a packet's lanes read different levels.
struct MipTables {
  Table16<std::int32_t> offsets, strides, last_x, last_y;
  Table16<float> widths, heights;
};
struct NoMipTables {};

template <int W, Addressing ADDRESSING, Taps TAPS = Taps::memory, Filter FILTER = Filter::bilinear>
class PacketSampler {
 public:
  using F = vfloat<W>;
  using I = vint<W>;
  using B = vbool<W>;

  explicit PacketSampler(const KernelTexture& t)
      : texels_(t.texels),
        chain_(t.levels),
        last_level_(t.level_count - 1),
        width0_(float(t.width)),
        height0_(float(t.height)),
        first_(uniform_level(0, t.width, t.height, t.stride)),
        second_(first_) {
    if constexpr (FILTER == Filter::trilinear)
      for (int l = 0; l < t.level_count; ++l) {
        const SamplerLevel& level = t.levels[l];
        tables_.offsets.values[l] = level.offset;
        tables_.strides.values[l] = level.width + 1;
        tables_.last_x.values[l] = level.width - 1;
        tables_.last_y.values[l] = level.height - 1;
        tables_.widths.values[l] = float(level.width);
        tables_.heights.values[l] = float(level.height);
      }
  }

  // Trilinear: the two levels of each lane and their blend weight, from its ray's gradients
  // (level_of_detail(), once per packet), before the packet's first sample.
  void set_footprint(F du_dx, F dv_dx, F du_dy, F dv_dy) {
    const F lod = level_of_detail(du_dx, dv_dx, du_dy, dv_dy, width0_, height0_, last_level_);
    const F first = floor(lod);
    weight_ = lod - first;
    const I d1 = to_int(first);
    first_ = level(d1);
    second_ = level(min(d1 + I(1), I(last_level_)));
  }

  F operator()(F u, F v) const { return operator()(texels_, u, v); }

  // The same read, levels included, of another texture of this one's layout (the cone map's
  // ratios beside its depths).
  F operator()(const float* texels, F u, F v) const {
    const F a = bilinear(texels, first_, u, v);
    if constexpr (FILTER == Filter::bilinear) {
      return a;
    } else {
      const F b = bilinear(texels, second_, u, v);
      return a + weight_ * (b - a);
    }
  }

 private:
  // A level's constants, per lane. `uniform`: every lane reads the level at `offset` (the coherent
  // fetch reads such a packet's taps); otherwise each lane's taps are gathered.
  struct Level {
    F width, height, inv_width, inv_height;
    I last_x, last_y, stride, offsets;
    bool uniform;
    std::int32_t offset, row_stride, rows;
  };

  static Level uniform_level(std::int32_t offset, int width, int height, int stride) {
    return {F(float(width)),
            F(float(height)),
            F(1.0f / float(width)),
            F(1.0f / float(height)),
            I(width - 1),
            I(height - 1),
            I(stride),
            I(offset),
            true,
            offset,
            stride,
            height + 1};
  }

  // The constants of each lane's level d, as one level's where every lane reads the same.
  Level level(I d) const {
    const std::int32_t lowest = reduce_min(d);
    if (none(I(lowest) < d)) {
      const SamplerLevel& l = chain_[lowest];
      return uniform_level(l.offset, l.width, l.height, l.width + 1);
    }
    const F width = lookup(tables_.widths, d), height = lookup(tables_.heights, d);
    return {width,
            height,
            F(1.0f) / width,
            F(1.0f) / height,
            lookup(tables_.last_x, d),
            lookup(tables_.last_y, d),
            lookup(tables_.strides, d),
            lookup(tables_.offsets, d),
            false,
            0,
            0,
            0};
  }

  F bilinear(const float* texels, const Level& l, F u, F v) const {
    F fx, fy;
    const I ix = texel_coordinate(u, l.width, l.inv_width, l.last_x, fx);
    const I iy = texel_coordinate(v, l.height, l.inv_height, l.last_y, fy);
    F t00, t10, t01, t11;
    if constexpr (TAPS == Taps::memory) {
      if (FILTER == Filter::bilinear || l.uniform) {
        fetch_taps(texels + l.offset, l.row_stride, l.rows, ix, iy, t00, t10, t01, t11);
      } else {
        const I index = l.offsets + iy * l.stride + ix;
        gather_pairs(texels, index, t00, t10);
        gather_pairs(texels, index + l.stride, t01, t11);
      }
    } else {
      const I index = iy * l.stride + ix;
      t00 = t10 = t01 = t11 = F(1.0f);
      register_pairs(index, t00, t10);
      register_pairs(index, t01, t11);
    }
    const F top = t00 + fx * (t10 - t00);
    const F bottom = t01 + fx * (t11 - t01);
    return top + fy * (bottom - top);
  }

  // Left tap index along one axis, and the blend weight of the right tap.
  static I texel_coordinate(F uv, F size, F inv_size, I last, F& weight) {
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
        return to_int(x0) & last;  // out of int range converts to INT32_MIN: index 0
      } else {
        // floor(x) wrapped into [0, size) in float: integer-valued, exact below 2^24.
        F i = x0 - size * floor(x0 * inv_size);
        i = select(i < F(0.0f), i + size, i);
        i = select(i >= size, i - size, i);
        return min(max(to_int(i), I(0)), last);
      }
    }
  }

  const float* texels_;
  const SamplerLevel* chain_;
  int last_level_;
  float width0_, height0_;
  Level first_, second_;  // bilinear: level 0 in both
  F weight_ = F(0.0f);
  [[no_unique_address]] std::conditional_t<FILTER == Filter::trilinear, MipTables, NoMipTables> tables_;
};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
