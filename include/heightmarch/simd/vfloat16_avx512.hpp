#pragma once
// Width 16: AVX-512F/BW/DQ/VL. Masks are k-registers.
#include <immintrin.h>

#include "heightmarch/simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <> struct vbool<16> {
  __mmask16 m;
  friend vbool operator&(vbool a, vbool c) { return {__mmask16(a.m & c.m)}; }
  friend vbool operator|(vbool a, vbool c) { return {__mmask16(a.m | c.m)}; }
  friend vbool operator!(vbool a) { return {__mmask16(~a.m)}; }
  friend bool any(vbool a) { return a.m != 0; }
  friend bool all(vbool a) { return a.m == 0xffff; }
  friend bool none(vbool a) { return a.m == 0; }
  friend int popcount(vbool a) { return __builtin_popcount(unsigned(a.m)); }
  static vbool all_true() { return {__mmask16(0xffff)}; }
};

template <> struct vint<16> {
  __m512i i;
  vint() = default;
  vint(__m512i x) : i(x) {}
  vint(std::int32_t x) : i(_mm512_set1_epi32(x)) {}
  friend vint operator+(vint a, vint c) { return _mm512_add_epi32(a.i, c.i); }
  friend vint operator-(vint a, vint c) { return _mm512_sub_epi32(a.i, c.i); }
  friend vint operator*(vint a, vint c) { return _mm512_mullo_epi32(a.i, c.i); }
  friend vint operator&(vint a, vint c) { return _mm512_and_si512(a.i, c.i); }
  friend vbool<16> operator<(vint a, vint c) { return {_mm512_cmplt_epi32_mask(a.i, c.i)}; }
  friend vint min(vint a, vint c) { return _mm512_min_epi32(a.i, c.i); }
  friend vint max(vint a, vint c) { return _mm512_max_epi32(a.i, c.i); }
  friend vint select(vbool<16> m, vint a, vint c) { return _mm512_mask_blend_epi32(m.m, c.i, a.i); }
  void store(std::int32_t* p) const { _mm512_storeu_si512(p, i); }
};

template <> struct vfloat<16> {
  __m512 f;
  static constexpr int width = 16;
  vfloat() = default;
  vfloat(__m512 x) : f(x) {}
  vfloat(float x) : f(_mm512_set1_ps(x)) {}
  static vfloat load(const float* p) { return _mm512_loadu_ps(p); }
  void store(float* p) const { _mm512_storeu_ps(p, f); }
  friend vfloat operator+(vfloat a, vfloat c) { return _mm512_add_ps(a.f, c.f); }
  friend vfloat operator-(vfloat a, vfloat c) { return _mm512_sub_ps(a.f, c.f); }
  friend vfloat operator*(vfloat a, vfloat c) { return _mm512_mul_ps(a.f, c.f); }
  friend vfloat operator/(vfloat a, vfloat c) { return _mm512_div_ps(a.f, c.f); }
  friend vbool<16> operator<(vfloat a, vfloat c) { return {_mm512_cmp_ps_mask(a.f, c.f, _CMP_LT_OQ)}; }
  friend vbool<16> operator>(vfloat a, vfloat c) { return {_mm512_cmp_ps_mask(a.f, c.f, _CMP_GT_OQ)}; }
  friend vbool<16> operator>=(vfloat a, vfloat c) { return {_mm512_cmp_ps_mask(a.f, c.f, _CMP_GE_OQ)}; }
  friend vbool<16> operator!=(vfloat a, vfloat c) { return {_mm512_cmp_ps_mask(a.f, c.f, _CMP_NEQ_UQ)}; }
  friend vfloat min(vfloat a, vfloat c) { return _mm512_min_ps(a.f, c.f); }
  friend vfloat max(vfloat a, vfloat c) { return _mm512_max_ps(a.f, c.f); }
  friend vfloat abs(vfloat a) { return _mm512_abs_ps(a.f); }
  friend vfloat floor(vfloat a) { return _mm512_roundscale_ps(a.f, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
  friend vfloat ceil(vfloat a) { return _mm512_roundscale_ps(a.f, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC); }
  friend vfloat select(vbool<16> m, vfloat a, vfloat c) { return _mm512_mask_blend_ps(m.m, c.f, a.f); }
  friend vint<16> to_int(vfloat a) { return _mm512_cvttps_epi32(a.f); }
  friend vfloat to_float(vint<16> a) { return _mm512_cvtepi32_ps(a.i); }
};

// base[index] and base[index + 1] of each lane: two 64-bit gathers of texel pairs instead of two
// 32-bit gathers of single texels (half the gathered elements), then deinterleaved. Unmasked:
// the sampler keeps every index inside the texture.
inline void gather_pairs(const float* base, vint<16> index, vfloat<16>& first, vfloat<16>& second) {
  const __m512 lo = _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_castsi512_si256(index.i), base, 4));
  const __m512 hi = _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_extracti64x4_epi64(index.i, 1), base, 4));
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  first = _mm512_permutex2var_ps(lo, even, hi);
  second = _mm512_permutex2var_ps(lo, odd, hi);
}
// The compute ceiling's stand-in for gather_pairs: first and second as if read at index, with no
// memory access. An empty asm the compiler cannot see through keeps the index computed and the
// taps opaque, so nothing of the bilinear arithmetic is folded or hoisted (zero instructions).
inline void register_pairs(vint<16> index, vfloat<16>& first, vfloat<16>& second) {
  asm volatile("" : "+v"(first.f), "+v"(second.f) : "v"(index.i));
}

// base[index] per lane.
inline vfloat<16> gather(const float* base, vint<16> index) { return _mm512_i32gather_ps(index.i, base, 4); }
inline vint<16> gather(const std::int32_t* base, vint<16> index) { return _mm512_i32gather_epi32(index.i, base, 4); }
inline vfloat<16> sqrt(vfloat<16> a) { return _mm512_sqrt_ps(a.f); }
// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<16> a) { return std::uint32_t(_mm512_reduce_add_epi32(a.i)); }
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<16> a, std::uint8_t* p) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm512_cvtepi32_epi8(a.i));
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
