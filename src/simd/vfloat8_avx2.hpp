#pragma once
// Width 8: AVX2 (+ FMA available, though the kernels do not contract; see src/isa/README.md).
#include <immintrin.h>

#include <algorithm>

#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<8> {
  __m256 m;  // all-ones lanes are true
  friend vbool operator&(vbool a, vbool c) { return {_mm256_and_ps(a.m, c.m)}; }
  friend vbool operator|(vbool a, vbool c) { return {_mm256_or_ps(a.m, c.m)}; }
  friend vbool operator!(vbool a) { return {_mm256_xor_ps(a.m, _mm256_castsi256_ps(_mm256_set1_epi32(-1)))}; }
  friend vbool and_not(vbool a, vbool c) { return {_mm256_andnot_ps(c.m, a.m)}; }
  friend bool any(vbool a) { return _mm256_movemask_ps(a.m) != 0; }
  friend bool all(vbool a) { return _mm256_movemask_ps(a.m) == 0xff; }
  friend bool none(vbool a) { return _mm256_movemask_ps(a.m) == 0; }
  static vbool all_true() { return {_mm256_castsi256_ps(_mm256_set1_epi32(-1))}; }
};

template <>
struct vint<8> {
  __m256i i;
  vint() = default;
  vint(__m256i x) : i(x) {}
  vint(std::int32_t x) : i(_mm256_set1_epi32(x)) {}
  friend vint operator+(vint a, vint c) { return _mm256_add_epi32(a.i, c.i); }
  friend vint operator-(vint a, vint c) { return _mm256_sub_epi32(a.i, c.i); }
  friend vint operator*(vint a, vint c) { return _mm256_mullo_epi32(a.i, c.i); }
  friend vint operator&(vint a, vint c) { return _mm256_and_si256(a.i, c.i); }
  friend vint operator|(vint a, vint c) { return _mm256_or_si256(a.i, c.i); }
  friend vint operator^(vint a, vint c) { return _mm256_xor_si256(a.i, c.i); }
  friend vint operator<<(vint a, vint n) { return _mm256_sllv_epi32(a.i, n.i); }
  friend vint operator<<(vint a, int n) { return _mm256_sll_epi32(a.i, _mm_cvtsi32_si128(n)); }
  friend vint operator>>(vint a, vint n) { return _mm256_srav_epi32(a.i, n.i); }
  friend vbool<8> operator<(vint a, vint c) { return {_mm256_castsi256_ps(_mm256_cmpgt_epi32(c.i, a.i))}; }
  friend vbool<8> operator==(vint a, vint c) { return {_mm256_castsi256_ps(_mm256_cmpeq_epi32(a.i, c.i))}; }
  friend vint min(vint a, vint c) { return _mm256_min_epi32(a.i, c.i); }
  friend vint max(vint a, vint c) { return _mm256_max_epi32(a.i, c.i); }
  friend vint select(vbool<8> m, vint a, vint c) {
    return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(c.i), _mm256_castsi256_ps(a.i), m.m));
  }
  static vint load(const std::int32_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  void store(std::int32_t* p) const { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), i); }
};

template <>
struct vfloat<8> {
  __m256 f;
  static constexpr int width = 8;
  vfloat() = default;
  vfloat(__m256 x) : f(x) {}
  vfloat(float x) : f(_mm256_set1_ps(x)) {}
  static vfloat load(const float* p) { return _mm256_loadu_ps(p); }
  void store(float* p) const { _mm256_storeu_ps(p, f); }
  friend vfloat operator+(vfloat a, vfloat c) { return _mm256_add_ps(a.f, c.f); }
  friend vfloat operator-(vfloat a, vfloat c) { return _mm256_sub_ps(a.f, c.f); }
  friend vfloat operator*(vfloat a, vfloat c) { return _mm256_mul_ps(a.f, c.f); }
  friend vfloat operator/(vfloat a, vfloat c) { return _mm256_div_ps(a.f, c.f); }
  friend vbool<8> operator<(vfloat a, vfloat c) { return {_mm256_cmp_ps(a.f, c.f, _CMP_LT_OQ)}; }
  friend vbool<8> operator>(vfloat a, vfloat c) { return {_mm256_cmp_ps(a.f, c.f, _CMP_GT_OQ)}; }
  friend vbool<8> operator>=(vfloat a, vfloat c) { return {_mm256_cmp_ps(a.f, c.f, _CMP_GE_OQ)}; }
  friend vbool<8> operator!=(vfloat a, vfloat c) { return {_mm256_cmp_ps(a.f, c.f, _CMP_NEQ_UQ)}; }
  friend vfloat min(vfloat a, vfloat c) { return _mm256_min_ps(a.f, c.f); }
  friend vfloat max(vfloat a, vfloat c) { return _mm256_max_ps(a.f, c.f); }
  friend vfloat abs(vfloat a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.f); }
  friend vfloat floor(vfloat a) { return _mm256_floor_ps(a.f); }
  friend vfloat ceil(vfloat a) { return _mm256_ceil_ps(a.f); }
  friend vfloat select(vbool<8> m, vfloat a, vfloat c) { return _mm256_blendv_ps(c.f, a.f, m.m); }
  friend vint<8> to_int(vfloat a) { return _mm256_cvttps_epi32(a.f); }
};
inline vfloat<8> to_float(vint<8> a) { return _mm256_cvtepi32_ps(a.i); }
inline vint<8> to_int(vbool<8> m) { return _mm256_castps_si256(m.m); }

inline constexpr int kDoubleWidth = 4;

template <>
struct vboold<4> {
  __m256d m;  // all-ones lanes are true
  friend vboold operator&(vboold a, vboold c) { return {_mm256_and_pd(a.m, c.m)}; }
  friend vboold operator|(vboold a, vboold c) { return {_mm256_or_pd(a.m, c.m)}; }
  friend vboold operator!(vboold a) {
    return {_mm256_xor_pd(a.m, _mm256_castsi256_pd(_mm256_set1_epi32(-1)))};
  }
  friend bool any(vboold a) { return _mm256_movemask_pd(a.m) != 0; }
};

template <>
struct vdouble<4> {
  __m256d d;
  vdouble() = default;
  vdouble(__m256d x) : d(x) {}
  vdouble(double x) : d(_mm256_set1_pd(x)) {}
  static vdouble load(const float* p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
  void store(float* p) const { _mm_storeu_ps(p, _mm256_cvtpd_ps(d)); }
  static vdouble load(const double* p) { return _mm256_loadu_pd(p); }
  void store(double* p) const { _mm256_storeu_pd(p, d); }
  friend vdouble operator+(vdouble a, vdouble c) { return _mm256_add_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a, vdouble c) { return _mm256_sub_pd(a.d, c.d); }
  friend vdouble operator*(vdouble a, vdouble c) { return _mm256_mul_pd(a.d, c.d); }
  friend vdouble operator/(vdouble a, vdouble c) { return _mm256_div_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a) { return _mm256_xor_pd(a.d, _mm256_set1_pd(-0.0)); }
  friend vboold<4> operator<(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_LT_OQ)}; }
  friend vboold<4> operator<=(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_LE_OQ)}; }
  friend vboold<4> operator>(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_GT_OQ)}; }
  friend vboold<4> operator>=(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_GE_OQ)}; }
  friend vboold<4> operator==(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_EQ_OQ)}; }
  friend vboold<4> operator!=(vdouble a, vdouble c) { return {_mm256_cmp_pd(a.d, c.d, _CMP_NEQ_UQ)}; }
  // minpd/maxpd return their second operand on NaN or equal values: swapped, std::min/max's pick.
  friend vdouble min(vdouble a, vdouble c) { return _mm256_min_pd(c.d, a.d); }
  friend vdouble max(vdouble a, vdouble c) { return _mm256_max_pd(c.d, a.d); }
  friend vdouble abs(vdouble a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a.d); }
  friend vdouble floor(vdouble a) { return _mm256_floor_pd(a.d); }
  friend vdouble sqrt(vdouble a) { return _mm256_sqrt_pd(a.d); }
  friend vdouble copysign(vdouble a, vdouble c) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    return _mm256_or_pd(_mm256_andnot_pd(sign, a.d), _mm256_and_pd(sign, c.d));
  }
  friend vdouble select(vboold<4> m, vdouble a, vdouble c) { return _mm256_blendv_pd(c.d, a.d, m.m); }
};

// base[index] and base[index + 1] of each lane: two 64-bit gathers of texel pairs instead of two
// 32-bit gathers of single texels (half the gathered elements), then deinterleaved. Unmasked:
// the sampler keeps every index inside the texture.
inline void gather_pairs(const float* base, vint<8> index, vfloat<8>& first, vfloat<8>& second) {
  const long long* pairs = reinterpret_cast<const long long*>(base);
  // Lanes 0 1 4 5 go to the low gather and 2 3 6 7 to the high one, so that shuffle_ps, which
  // works within 128-bit halves, leaves them in order (one index permute, shared by both rows'
  // calls, instead of a permute of each result).
  const __m256i order = _mm256_permute4x64_epi64(index.i, _MM_SHUFFLE(3, 1, 2, 0));
  const __m256 lo = _mm256_castsi256_ps(_mm256_i32gather_epi64(pairs, _mm256_castsi256_si128(order), 4));
  const __m256 hi = _mm256_castsi256_ps(_mm256_i32gather_epi64(pairs, _mm256_extracti128_si256(order, 1), 4));
  first = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
  second = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
}
// The compute ceiling's stand-in for gather_pairs: first and second as if read at index, with no
// memory access. An empty asm the compiler cannot see through keeps the index computed and the
// taps opaque, so nothing of the bilinear arithmetic is folded or hoisted (zero instructions).
inline void register_pairs(vint<8> index, vfloat<8>& first, vfloat<8>& second) {
  asm volatile("" : "+x"(first.f), "+x"(second.f) : "x"(index.i));
}

// fetch_taps (packet.hpp) with a coherent path: when every lane's taps lie in lane 0's texel row
// (and the next) within the 8 columns from lane 0's (a packet of 8 rays of one pixel row:
// heightmarch/rays.hpp), the two rows are read with two loads and each tap picked by a permute;
// otherwise the gathers (each vpgatherdq of 4 pairs costs about 6 cycles on AMD Zen 5).
inline void fetch_taps(const float* texels, std::int32_t stride, std::int32_t rows, vint<8> ix, vint<8> iy,
                       vfloat<8>& t00, vfloat<8>& t10, vfloat<8>& t01, vfloat<8>& t11) {
  (void)rows;  // lane 0's row has one below it: the texture's extra row
  // The window's first column: lane 0's, moved left where the row would end inside the window.
  const std::int32_t x0 = std::min(_mm256_cvtsi256_si32(ix.i), stride - 8);
  const std::int32_t y0 = _mm256_cvtsi256_si32(iy.i);
  const __m256i dx = _mm256_sub_epi32(ix.i, _mm256_set1_epi32(x0));
  const __m256i same_row = _mm256_cmpeq_epi32(iy.i, _mm256_set1_epi32(y0));
  const __m256i in_columns =
      _mm256_cmpeq_epi32(_mm256_min_epu32(dx, _mm256_set1_epi32(6)), dx);  // 0 <= dx <= 6
  if (_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_and_si256(same_row, in_columns))) == 0xff &&
      stride >= 8) {
    const float* row = texels + std::ptrdiff_t(y0) * stride + x0;
    const __m256 row0 = _mm256_loadu_ps(row), row1 = _mm256_loadu_ps(row + stride);
    const __m256i right = _mm256_add_epi32(dx, _mm256_set1_epi32(1));
    t00 = _mm256_permutevar8x32_ps(row0, dx);
    t10 = _mm256_permutevar8x32_ps(row0, right);
    t01 = _mm256_permutevar8x32_ps(row1, dx);
    t11 = _mm256_permutevar8x32_ps(row1, right);
    return;
  }
  const vint<8> index = iy * vint<8>(stride) + ix;
  gather_pairs(texels, index, t00, t10);
  gather_pairs(texels + stride, index, t01, t11);
}

// lookup() (packet.hpp) with two permutes of the table's halves, blended on bit 3 of the index.
inline __m256 lookup_halves(__m256 low, __m256 high, vint<8> index) {
  return _mm256_blendv_ps(_mm256_permutevar8x32_ps(low, index.i), _mm256_permutevar8x32_ps(high, index.i),
                          _mm256_castsi256_ps(_mm256_slli_epi32(index.i, 28)));
}
inline vfloat<8> lookup(const Table16<float>& table, vint<8> index) {
  return lookup_halves(_mm256_load_ps(table.values), _mm256_load_ps(table.values + 8), index);
}
inline vint<8> lookup(const Table16<std::int32_t>& table, vint<8> index) {
  const __m256i* halves = reinterpret_cast<const __m256i*>(table.values);
  return _mm256_castps_si256(lookup_halves(_mm256_castsi256_ps(_mm256_load_si256(halves)),
                                           _mm256_castsi256_ps(_mm256_load_si256(halves + 1)), index));
}

// base[index] per lane.
inline vfloat<8> gather(const float* base, vint<8> index) { return _mm256_i32gather_ps(base, index.i, 4); }
inline vint<8> gather(const std::int32_t* base, vint<8> index) {
  return _mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index.i, 4);
}
// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<8> a) {
  __m128i s = _mm_add_epi32(_mm256_castsi256_si128(a.i), _mm256_extracti128_si256(a.i, 1));
  s = _mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(1, 0, 3, 2)));
  return std::uint32_t(_mm_cvtsi128_si32(_mm_add_epi32(s, _mm_shuffle_epi32(s, _MM_SHUFFLE(2, 3, 0, 1)))));
}
// The smallest lane.
inline std::int32_t reduce_min(vint<8> a) {
  __m128i m = _mm_min_epi32(_mm256_castsi256_si128(a.i), _mm256_extracti128_si256(a.i, 1));
  m = _mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtsi128_si32(_mm_min_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1))));
}
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<8> a, std::uint8_t* p) {
  const __m128i words = _mm_packs_epi32(_mm256_castsi256_si128(a.i), _mm256_extracti128_si256(a.i, 1));
  _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_packus_epi16(words, words));
}
inline vfloat<8> sqrt(vfloat<8> a) { return _mm256_sqrt_ps(a.f); }

// 2^n built from its exponent bits.
inline vfloat<8> pow2(vint<8> n) {
  return _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(n.i, _mm256_set1_epi32(127)), 23));
}
inline std::uint32_t mask_bits(vbool<8> m) { return std::uint32_t(_mm256_movemask_ps(m.m)); }

// For each mask of 8 lanes, one byte per lane: the number of true lanes below it (expand), and
// the k-th true lane at byte k (compress).
struct LanePermutes8 {
  std::uint64_t expand[256] = {};
  std::uint64_t compress[256] = {};
  constexpr LanePermutes8() {
    for (int mask = 0; mask < 256; ++mask)
      for (int lane = 0, below = 0; lane < 8; ++lane) {
        expand[mask] |= std::uint64_t(below) << (8 * lane);
        if ((mask >> lane) & 1) compress[mask] |= std::uint64_t(lane) << (8 * below++);
      }
  }
};
inline constexpr LanePermutes8 kLanePermutes8{};

inline __m256i lane_permute(std::uint64_t bytes) {
  return _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(std::int64_t(bytes)));
}

// expand_load() and compress_store() (packet.hpp) with one permute.
inline vfloat<8> expand_load(const float* p, vbool<8> m, vfloat<8> old) {
  const __m256i rank = lane_permute(kLanePermutes8.expand[_mm256_movemask_ps(m.m)]);
  return _mm256_blendv_ps(old.f, _mm256_permutevar8x32_ps(_mm256_loadu_ps(p), rank), m.m);
}
inline vint<8> expand_load(const std::int32_t* p, vbool<8> m, vint<8> old) {
  const __m256i rank = lane_permute(kLanePermutes8.expand[_mm256_movemask_ps(m.m)]);
  const __m256i spread =
      _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)), rank);
  return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(old.i), _mm256_castsi256_ps(spread), m.m));
}
inline void compress_store(float* p, vbool<8> m, vfloat<8> value) {
  _mm256_storeu_ps(
      p, _mm256_permutevar8x32_ps(value.f, lane_permute(kLanePermutes8.compress[_mm256_movemask_ps(m.m)])));
}
inline void compress_store(std::int32_t* p, vbool<8> m, vint<8> value) {
  _mm256_storeu_si256(
      reinterpret_cast<__m256i*>(p),
      _mm256_permutevar8x32_epi32(value.i, lane_permute(kLanePermutes8.compress[_mm256_movemask_ps(m.m)])));
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
