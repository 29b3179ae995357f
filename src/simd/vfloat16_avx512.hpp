#pragma once
// Width 16: AVX-512F/BW/DQ/VL. Masks are k-registers.
#include <immintrin.h>

#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<16> {
  __mmask16 m;
  friend vbool operator&(vbool a, vbool c) { return {__mmask16(a.m & c.m)}; }
  friend vbool operator|(vbool a, vbool c) { return {__mmask16(a.m | c.m)}; }
  friend vbool operator!(vbool a) { return {__mmask16(~a.m)}; }
  friend vbool and_not(vbool a, vbool c) { return {__mmask16(a.m & ~c.m)}; }
  friend bool any(vbool a) { return a.m != 0; }
  friend bool all(vbool a) { return a.m == 0xffff; }
  friend bool none(vbool a) { return a.m == 0; }
  static vbool all_true() { return {__mmask16(0xffff)}; }
};

template <>
struct vint<16> {
  __m512i i;
  vint() = default;
  vint(__m512i x) : i(x) {}
  vint(std::int32_t x) : i(_mm512_set1_epi32(x)) {}
  friend vint operator+(vint a, vint c) { return _mm512_add_epi32(a.i, c.i); }
  friend vint operator-(vint a, vint c) { return _mm512_sub_epi32(a.i, c.i); }
  friend vint operator*(vint a, vint c) { return _mm512_mullo_epi32(a.i, c.i); }
  friend vint operator&(vint a, vint c) { return _mm512_and_si512(a.i, c.i); }
  friend vint operator|(vint a, vint c) { return _mm512_or_si512(a.i, c.i); }
  friend vint operator^(vint a, vint c) { return _mm512_xor_si512(a.i, c.i); }
  friend vint operator<<(vint a, vint n) { return _mm512_sllv_epi32(a.i, n.i); }
  friend vint operator<<(vint a, int n) { return _mm512_sll_epi32(a.i, _mm_cvtsi32_si128(n)); }
  friend vint operator>>(vint a, vint n) { return _mm512_srav_epi32(a.i, n.i); }
  friend vbool<16> operator<(vint a, vint c) { return {_mm512_cmplt_epi32_mask(a.i, c.i)}; }
  friend vbool<16> operator==(vint a, vint c) { return {_mm512_cmpeq_epi32_mask(a.i, c.i)}; }
  friend vint min(vint a, vint c) { return _mm512_min_epi32(a.i, c.i); }
  friend vint max(vint a, vint c) { return _mm512_max_epi32(a.i, c.i); }
  friend vint select(vbool<16> m, vint a, vint c) { return _mm512_mask_blend_epi32(m.m, c.i, a.i); }
  static vint load(const std::int32_t* p) { return _mm512_loadu_si512(p); }
  void store(std::int32_t* p) const { _mm512_storeu_si512(p, i); }
};

template <>
struct vfloat<16> {
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
  friend vfloat floor(vfloat a) {
    return _mm512_roundscale_ps(a.f, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  }
  friend vfloat ceil(vfloat a) {
    return _mm512_roundscale_ps(a.f, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
  }
  friend vfloat select(vbool<16> m, vfloat a, vfloat c) { return _mm512_mask_blend_ps(m.m, c.f, a.f); }
  friend vint<16> to_int(vfloat a) { return _mm512_cvttps_epi32(a.f); }
};
inline vfloat<16> to_float(vint<16> a) { return _mm512_cvtepi32_ps(a.i); }
inline vint<16> to_int(vbool<16> m) { return _mm512_movm_epi32(m.m); }

inline constexpr int kDoubleWidth = 8;

template <>
struct vboold<8> {
  __mmask8 m;
  friend vboold operator&(vboold a, vboold c) { return {__mmask8(a.m & c.m)}; }
  friend vboold operator|(vboold a, vboold c) { return {__mmask8(a.m | c.m)}; }
  friend vboold operator!(vboold a) { return {__mmask8(~a.m)}; }
  friend bool any(vboold a) { return a.m != 0; }
};

template <>
struct vdouble<8> {
  __m512d d;
  vdouble() = default;
  vdouble(__m512d x) : d(x) {}
  vdouble(double x) : d(_mm512_set1_pd(x)) {}
  static vdouble load(const float* p) { return _mm512_cvtps_pd(_mm256_loadu_ps(p)); }
  void store(float* p) const { _mm256_storeu_ps(p, _mm512_cvtpd_ps(d)); }
  static vdouble load(const double* p) { return _mm512_loadu_pd(p); }
  void store(double* p) const { _mm512_storeu_pd(p, d); }
  friend vdouble operator+(vdouble a, vdouble c) { return _mm512_add_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a, vdouble c) { return _mm512_sub_pd(a.d, c.d); }
  friend vdouble operator*(vdouble a, vdouble c) { return _mm512_mul_pd(a.d, c.d); }
  friend vdouble operator/(vdouble a, vdouble c) { return _mm512_div_pd(a.d, c.d); }
  friend vdouble operator-(vdouble a) { return _mm512_xor_pd(a.d, _mm512_set1_pd(-0.0)); }
  friend vboold<8> operator<(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_LT_OQ)}; }
  friend vboold<8> operator<=(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_LE_OQ)}; }
  friend vboold<8> operator>(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_GT_OQ)}; }
  friend vboold<8> operator>=(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_GE_OQ)}; }
  friend vboold<8> operator==(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_EQ_OQ)}; }
  friend vboold<8> operator!=(vdouble a, vdouble c) { return {_mm512_cmp_pd_mask(a.d, c.d, _CMP_NEQ_UQ)}; }
  // minpd/maxpd return their second operand on NaN or equal values: swapped, std::min/max's pick.
  friend vdouble min(vdouble a, vdouble c) { return _mm512_min_pd(c.d, a.d); }
  friend vdouble max(vdouble a, vdouble c) { return _mm512_max_pd(c.d, a.d); }
  friend vdouble abs(vdouble a) { return _mm512_abs_pd(a.d); }
  friend vdouble floor(vdouble a) {
    return _mm512_roundscale_pd(a.d, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  }
  friend vdouble sqrt(vdouble a) { return _mm512_sqrt_pd(a.d); }
  friend vdouble copysign(vdouble a, vdouble c) {
    const __m512d sign = _mm512_set1_pd(-0.0);
    return _mm512_or_pd(_mm512_andnot_pd(sign, a.d), _mm512_and_pd(sign, c.d));
  }
  friend vdouble select(vboold<8> m, vdouble a, vdouble c) { return _mm512_mask_blend_pd(m.m, c.d, a.d); }
};

// base[index] and base[index + 1] of each lane: two 64-bit gathers of texel pairs instead of two
// 32-bit gathers of single texels (half the gathered elements), then deinterleaved. Unmasked:
// the sampler keeps every index inside the texture.
inline void gather_pairs(const float* base, vint<16> index, vfloat<16>& first, vfloat<16>& second) {
  const __m512 lo = _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_castsi512_si256(index.i), base, 4));
  const __m512 hi =
      _mm512_castsi512_ps(_mm512_i32gather_epi64(_mm512_extracti64x4_epi64(index.i, 1), base, 4));
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

// fetch_taps (packet.hpp) with a coherent path: when every lane's taps lie in the 8-column x
// 5-row window around lane 0's (2 columns left, 3 rows up: where the taps of a packet of two
// pixel rows of 8 fall at one layer step, measured on the default view), the window is read with
// five row loads and each tap picked by a two-table permute; otherwise the gathers.
inline void fetch_taps(const float* texels, std::int32_t stride, std::int32_t rows, vint<16> ix, vint<16> iy,
                       vfloat<16>& t00, vfloat<16>& t10, vfloat<16>& t01, vfloat<16>& t11) {
  const std::int32_t x0 = _mm_cvtsi128_si32(_mm512_castsi512_si128(ix.i)) - 2;
  const std::int32_t y0 = _mm_cvtsi128_si32(_mm512_castsi512_si128(iy.i)) - 3;
  const __m512i dx = _mm512_sub_epi32(ix.i, _mm512_set1_epi32(x0));
  const __m512i dy = _mm512_sub_epi32(iy.i, _mm512_set1_epi32(y0));
  // Taps in columns x0 .. x0 + 7 and rows y0 .. y0 + 4, all inside the texture's allocation.
  const __mmask16 inside =
      _mm512_cmple_epu32_mask(dx, _mm512_set1_epi32(6)) & _mm512_cmple_epu32_mask(dy, _mm512_set1_epi32(3));
  if (inside == 0xffff && x0 >= 0 && y0 >= 0 && x0 + 8 <= stride && y0 + 5 <= rows) {
    const float* row = texels + std::ptrdiff_t(y0) * stride + x0;
    auto two_rows = [&](int r) {  // rows r and r + 1 of the window, 8 texels each
      return _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(row + std::ptrdiff_t(r) * stride)),
                                _mm256_loadu_ps(row + std::ptrdiff_t(r + 1) * stride), 1);
    };
    const __m512 rows01 = two_rows(0), rows23 = two_rows(2), rows12 = two_rows(1), rows34 = two_rows(3);
    // A lane's tap at (dx, dy) is entry 8 dy + dx of [rows01 | rows23]; the row below it, the same
    // entry of [rows12 | rows34].
    const __m512i at = _mm512_add_epi32(_mm512_slli_epi32(dy, 3), dx);
    const __m512i right = _mm512_add_epi32(at, _mm512_set1_epi32(1));
    t00 = _mm512_permutex2var_ps(rows01, at, rows23);
    t10 = _mm512_permutex2var_ps(rows01, right, rows23);
    t01 = _mm512_permutex2var_ps(rows12, at, rows34);
    t11 = _mm512_permutex2var_ps(rows12, right, rows34);
    return;
  }
  const vint<16> index = iy * vint<16>(stride) + ix;
  gather_pairs(texels, index, t00, t10);
  gather_pairs(texels + stride, index, t01, t11);
}

// lookup() (packet.hpp) with one register permute.
inline vfloat<16> lookup(const Table16<float>& table, vint<16> index) {
  return _mm512_permutexvar_ps(index.i, _mm512_load_ps(table.values));
}
inline vint<16> lookup(const Table16<std::int32_t>& table, vint<16> index) {
  return _mm512_permutexvar_epi32(index.i, _mm512_load_si512(table.values));
}

// base[index] per lane.
inline vfloat<16> gather(const float* base, vint<16> index) { return _mm512_i32gather_ps(index.i, base, 4); }
inline vint<16> gather(const std::int32_t* base, vint<16> index) {
  return _mm512_i32gather_epi32(index.i, base, 4);
}
inline vfloat<16> sqrt(vfloat<16> a) { return _mm512_sqrt_ps(a.f); }
// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<16> a) { return std::uint32_t(_mm512_reduce_add_epi32(a.i)); }
// The smallest lane.
inline std::int32_t reduce_min(vint<16> a) { return _mm512_reduce_min_epi32(a.i); }
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<16> a, std::uint8_t* p) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm512_cvtepi32_epi8(a.i));
}

// 2^n built from its exponent bits.
inline vfloat<16> pow2(vint<16> n) {
  return _mm512_castsi512_ps(_mm512_slli_epi32(_mm512_add_epi32(n.i, _mm512_set1_epi32(127)), 23));
}
inline std::uint32_t mask_bits(vbool<16> m) { return m.m; }
// expand_load(), compress_store() and scatter() (packet.hpp) with the ISA's expand, compress
// (in registers: their memory forms are microcoded on some cores) and scatter.
inline vfloat<16> expand_load(const float* p, vbool<16> m, vfloat<16> old) {
  return _mm512_mask_expand_ps(old.f, m.m, _mm512_loadu_ps(p));
}
inline vint<16> expand_load(const std::int32_t* p, vbool<16> m, vint<16> old) {
  return _mm512_mask_expand_epi32(old.i, m.m, _mm512_loadu_si512(p));
}
inline void compress_store(float* p, vbool<16> m, vfloat<16> value) {
  _mm512_storeu_ps(p, _mm512_maskz_compress_ps(m.m, value.f));
}
inline void compress_store(std::int32_t* p, vbool<16> m, vint<16> value) {
  _mm512_storeu_si512(p, _mm512_maskz_compress_epi32(m.m, value.i));
}
inline void scatter(float* base, vint<16> index, vbool<16> m, vfloat<16> value) {
  _mm512_mask_i32scatter_ps(base, m.m, index.i, value.f, 4);
}
inline void scatter(std::int32_t* base, vint<16> index, vbool<16> m, vint<16> value) {
  _mm512_mask_i32scatter_epi32(base, m.m, index.i, value.i, 4);
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
