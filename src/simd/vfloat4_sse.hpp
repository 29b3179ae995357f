#pragma once
// Width 4: SSE4.2. SSE has no gather: see gather_pairs.
#include <nmmintrin.h>

#include <cstring>

#include "simd/lane_shuffles4.hpp"
#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<4> {
  __m128 m;  // all-ones lanes are true
  friend vbool operator&(vbool a, vbool c) { return {_mm_and_ps(a.m, c.m)}; }
  friend vbool operator|(vbool a, vbool c) { return {_mm_or_ps(a.m, c.m)}; }
  friend vbool operator!(vbool a) { return {_mm_xor_ps(a.m, _mm_castsi128_ps(_mm_set1_epi32(-1)))}; }
  friend vbool and_not(vbool a, vbool c) { return {_mm_andnot_ps(c.m, a.m)}; }
  friend bool any(vbool a) { return _mm_movemask_ps(a.m) != 0; }
  friend bool all(vbool a) { return _mm_movemask_ps(a.m) == 0xf; }
  friend bool none(vbool a) { return _mm_movemask_ps(a.m) == 0; }
  static vbool all_true() { return {_mm_castsi128_ps(_mm_set1_epi32(-1))}; }
};

// SSE has no shift by per-lane counts: the register is shifted by each lane's count (SSE's count
// is the low 64 bits of a register) and each lane taken from its own shift.
template <bool LEFT>
inline __m128i shift_lanes(__m128i a, __m128i n) {
  const __m128i low = _mm_set_epi32(0, 0, 0, -1);
  const auto by = [&](__m128i count) { return LEFT ? _mm_sll_epi32(a, count) : _mm_sra_epi32(a, count); };
  const __m128i r0 = by(_mm_and_si128(n, low)), r1 = by(_mm_srli_epi64(n, 32));
  const __m128i r2 = by(_mm_and_si128(_mm_unpackhi_epi64(n, n), low)), r3 = by(_mm_srli_si128(n, 12));
  return _mm_blend_epi16(_mm_blend_epi16(r0, r1, 0x0c), _mm_blend_epi16(r2, r3, 0xc0), 0xf0);
}

template <>
struct vint<4> {
  __m128i i;
  vint() = default;
  vint(__m128i x) : i(x) {}
  vint(std::int32_t x) : i(_mm_set1_epi32(x)) {}
  friend vint operator+(vint a, vint c) { return _mm_add_epi32(a.i, c.i); }
  friend vint operator-(vint a, vint c) { return _mm_sub_epi32(a.i, c.i); }
  friend vint operator*(vint a, vint c) { return _mm_mullo_epi32(a.i, c.i); }
  friend vint operator&(vint a, vint c) { return _mm_and_si128(a.i, c.i); }
  friend vint operator|(vint a, vint c) { return _mm_or_si128(a.i, c.i); }
  friend vint operator^(vint a, vint c) { return _mm_xor_si128(a.i, c.i); }
  friend vint operator<<(vint a, vint n) { return shift_lanes<true>(a.i, n.i); }
  friend vint operator<<(vint a, int n) { return _mm_sll_epi32(a.i, _mm_cvtsi32_si128(n)); }
  friend vint operator>>(vint a, vint n) { return shift_lanes<false>(a.i, n.i); }
  friend vbool<4> operator<(vint a, vint c) { return {_mm_castsi128_ps(_mm_cmplt_epi32(a.i, c.i))}; }
  friend vbool<4> operator==(vint a, vint c) { return {_mm_castsi128_ps(_mm_cmpeq_epi32(a.i, c.i))}; }
  friend vint min(vint a, vint c) { return _mm_min_epi32(a.i, c.i); }
  friend vint max(vint a, vint c) { return _mm_max_epi32(a.i, c.i); }
  friend vint select(vbool<4> m, vint a, vint c) {
    return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(c.i), _mm_castsi128_ps(a.i), m.m));
  }
  static vint load(const std::int32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
  void store(std::int32_t* p) const { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), i); }
};

template <>
struct vfloat<4> {
  __m128 f;
  static constexpr int width = 4;
  vfloat() = default;
  vfloat(__m128 x) : f(x) {}
  vfloat(float x) : f(_mm_set1_ps(x)) {}
  static vfloat load(const float* p) { return _mm_loadu_ps(p); }
  void store(float* p) const { _mm_storeu_ps(p, f); }
  friend vfloat operator+(vfloat a, vfloat c) { return _mm_add_ps(a.f, c.f); }
  friend vfloat operator-(vfloat a, vfloat c) { return _mm_sub_ps(a.f, c.f); }
  friend vfloat operator*(vfloat a, vfloat c) { return _mm_mul_ps(a.f, c.f); }
  friend vfloat operator/(vfloat a, vfloat c) { return _mm_div_ps(a.f, c.f); }
  friend vbool<4> operator<(vfloat a, vfloat c) { return {_mm_cmplt_ps(a.f, c.f)}; }
  friend vbool<4> operator>(vfloat a, vfloat c) { return {_mm_cmpgt_ps(a.f, c.f)}; }
  friend vbool<4> operator>=(vfloat a, vfloat c) { return {_mm_cmpge_ps(a.f, c.f)}; }
  friend vbool<4> operator!=(vfloat a, vfloat c) { return {_mm_cmpneq_ps(a.f, c.f)}; }
  friend vfloat min(vfloat a, vfloat c) { return _mm_min_ps(a.f, c.f); }
  friend vfloat max(vfloat a, vfloat c) { return _mm_max_ps(a.f, c.f); }
  friend vfloat abs(vfloat a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a.f); }
  friend vfloat floor(vfloat a) { return _mm_floor_ps(a.f); }
  friend vfloat ceil(vfloat a) { return _mm_ceil_ps(a.f); }
  friend vfloat select(vbool<4> m, vfloat a, vfloat c) { return _mm_blendv_ps(c.f, a.f, m.m); }
  friend vint<4> to_int(vfloat a) { return _mm_cvttps_epi32(a.f); }
};
inline vfloat<4> to_float(vint<4> a) { return _mm_cvtepi32_ps(a.i); }
inline vint<4> to_int(vbool<4> m) { return _mm_castps_si128(m.m); }

inline constexpr int kDoubleWidth = 2;

template <>
struct vboold<2> {
  __m128d m;  // all-ones lanes are true
  friend vboold operator&(vboold a, vboold c) { return {_mm_and_pd(a.m, c.m)}; }
  friend vboold operator|(vboold a, vboold c) { return {_mm_or_pd(a.m, c.m)}; }
  friend vboold operator!(vboold a) { return {_mm_xor_pd(a.m, _mm_castsi128_pd(_mm_set1_epi32(-1)))}; }
  friend bool any(vboold a) { return _mm_movemask_pd(a.m) != 0; }
};

template <>
struct vdouble<2> {
  __m128d d;
  vdouble() = default;
  vdouble(__m128d x) : d(x) {}
  vdouble(double x) : d(_mm_set1_pd(x)) {}
  static vdouble load(const float* p) {
    return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
  }
  void store(float* p) const {
    _mm_storel_epi64(reinterpret_cast<__m128i*>(p), _mm_castps_si128(_mm_cvtpd_ps(d)));
  }
  static vdouble load(const double* p) { return _mm_loadu_pd(p); }
  void store(double* p) const { _mm_storeu_pd(p, d); }
  friend vdouble operator+(vdouble a, vdouble c) { return _mm_add_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a, vdouble c) { return _mm_sub_pd(a.d, c.d); }
  friend vdouble operator*(vdouble a, vdouble c) { return _mm_mul_pd(a.d, c.d); }
  friend vdouble operator/(vdouble a, vdouble c) { return _mm_div_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a) { return _mm_xor_pd(a.d, _mm_set1_pd(-0.0)); }
  friend vboold<2> operator<(vdouble a, vdouble c) { return {_mm_cmplt_pd(a.d, c.d)}; }
  friend vboold<2> operator<=(vdouble a, vdouble c) { return {_mm_cmple_pd(a.d, c.d)}; }
  friend vboold<2> operator>(vdouble a, vdouble c) { return {_mm_cmpgt_pd(a.d, c.d)}; }
  friend vboold<2> operator>=(vdouble a, vdouble c) { return {_mm_cmpge_pd(a.d, c.d)}; }
  friend vboold<2> operator==(vdouble a, vdouble c) { return {_mm_cmpeq_pd(a.d, c.d)}; }
  friend vboold<2> operator!=(vdouble a, vdouble c) { return {_mm_cmpneq_pd(a.d, c.d)}; }
  // minpd/maxpd return their second operand on NaN or equal values: swapped, std::min/max's pick.
  friend vdouble min(vdouble a, vdouble c) { return _mm_min_pd(c.d, a.d); }
  friend vdouble max(vdouble a, vdouble c) { return _mm_max_pd(c.d, a.d); }
  friend vdouble abs(vdouble a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a.d); }
  friend vdouble floor(vdouble a) { return _mm_floor_pd(a.d); }
  friend vdouble sqrt(vdouble a) { return _mm_sqrt_pd(a.d); }
  friend vdouble copysign(vdouble a, vdouble c) {
    const __m128d sign = _mm_set1_pd(-0.0);
    return _mm_or_pd(_mm_andnot_pd(sign, a.d), _mm_and_pd(sign, c.d));
  }
  friend vdouble select(vboold<2> m, vdouble a, vdouble c) { return _mm_blendv_pd(c.d, a.d, m.m); }
};

// base[index] and base[index + 1] of each lane. SSE has no gather: one 64-bit load per lane
// fetches both texels, then two shuffles deinterleave them (half the loads of four scalar
// gathers).
inline void gather_pairs(const float* base, vint<4> index, vfloat<4>& first, vfloat<4>& second) {
  const long long lo = _mm_cvtsi128_si64(index.i);
  const long long hi = _mm_extract_epi64(index.i, 1);
  // memcpy: texel pairs are only 4-byte aligned (a compiled-out copy, one movq).
  auto pair = [&](std::int32_t i) {
    long long bits;
    std::memcpy(&bits, base + i, sizeof bits);
    return _mm_castsi128_ps(_mm_cvtsi64_si128(bits));
  };
  const __m128 p01 = _mm_movelh_ps(pair(std::int32_t(lo)), pair(std::int32_t(lo >> 32)));  // a0 b0 a1 b1
  const __m128 p23 = _mm_movelh_ps(pair(std::int32_t(hi)), pair(std::int32_t(hi >> 32)));  // a2 b2 a3 b3
  first = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(2, 0, 2, 0));
  second = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(3, 1, 3, 1));
}
// The compute ceiling's stand-in for gather_pairs: first and second as if read at index, with no
// memory access. An empty asm the compiler cannot see through keeps the index computed and the
// taps opaque, so nothing of the bilinear arithmetic is folded or hoisted (zero instructions).
inline void register_pairs(vint<4> index, vfloat<4>& first, vfloat<4>& second) {
  asm volatile("" : "+x"(first.f), "+x"(second.f) : "x"(index.i));
}

// base[index] per lane (no gather on SSE: four scalar loads).
inline vfloat<4> gather(const float* base, vint<4> index) {
  return _mm_setr_ps(base[_mm_extract_epi32(index.i, 0)], base[_mm_extract_epi32(index.i, 1)],
                     base[_mm_extract_epi32(index.i, 2)], base[_mm_extract_epi32(index.i, 3)]);
}
inline vint<4> gather(const std::int32_t* base, vint<4> index) {
  return _mm_setr_epi32(base[_mm_extract_epi32(index.i, 0)], base[_mm_extract_epi32(index.i, 1)],
                        base[_mm_extract_epi32(index.i, 2)], base[_mm_extract_epi32(index.i, 3)]);
}
// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<4> a) {
  const __m128i pairs = _mm_add_epi32(a.i, _mm_shuffle_epi32(a.i, _MM_SHUFFLE(1, 0, 3, 2)));
  return std::uint32_t(
      _mm_cvtsi128_si32(_mm_add_epi32(pairs, _mm_shuffle_epi32(pairs, _MM_SHUFFLE(2, 3, 0, 1)))));
}
// The smallest lane.
inline std::int32_t reduce_min(vint<4> a) {
  const __m128i pairs = _mm_min_epi32(a.i, _mm_shuffle_epi32(a.i, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtsi128_si32(_mm_min_epi32(pairs, _mm_shuffle_epi32(pairs, _MM_SHUFFLE(2, 3, 0, 1))));
}
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<4> a, std::uint8_t* p) {
  const __m128i words = _mm_packs_epi32(a.i, a.i);
  const std::int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(words, words));
  std::memcpy(p, &bytes, sizeof bytes);
}
inline vfloat<4> sqrt(vfloat<4> a) { return _mm_sqrt_ps(a.f); }

// 2^n built from its exponent bits.
inline vfloat<4> pow2(vint<4> n) {
  return _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(n.i, _mm_set1_epi32(127)), 23));
}
inline std::uint32_t mask_bits(vbool<4> m) { return std::uint32_t(_mm_movemask_ps(m.m)); }

// expand_load() and compress_store() (packet.hpp) with one shuffle (lane_shuffles4.hpp).
inline __m128i expand_lanes(__m128i loaded, vbool<4> m, __m128i old) {
  const __m128i control =
      _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneShuffles4.expand[_mm_movemask_ps(m.m)]));
  return _mm_castps_si128(
      _mm_blendv_ps(_mm_castsi128_ps(old), _mm_castsi128_ps(_mm_shuffle_epi8(loaded, control)), m.m));
}
inline __m128i compress_lanes(__m128i value, vbool<4> m) {
  const __m128i control =
      _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneShuffles4.compress[_mm_movemask_ps(m.m)]));
  return _mm_shuffle_epi8(value, control);
}
inline vfloat<4> expand_load(const float* p, vbool<4> m, vfloat<4> old) {
  return _mm_castsi128_ps(expand_lanes(_mm_castps_si128(_mm_loadu_ps(p)), m, _mm_castps_si128(old.f)));
}
inline vint<4> expand_load(const std::int32_t* p, vbool<4> m, vint<4> old) {
  return expand_lanes(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), m, old.i);
}
inline void compress_store(float* p, vbool<4> m, vfloat<4> value) {
  _mm_storeu_ps(p, _mm_castsi128_ps(compress_lanes(_mm_castps_si128(value.f), m)));
}
inline void compress_store(std::int32_t* p, vbool<4> m, vint<4> value) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), compress_lanes(value.i, m));
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
