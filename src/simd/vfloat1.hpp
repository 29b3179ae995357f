#pragma once
// Width 1: plain scalar code, so that the packet kernels compile as the scalar reference.
#include <cmath>
#include <cstdint>

#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<1> {
  bool b;
  friend vbool operator&(vbool a, vbool c) { return {a.b && c.b}; }
  friend vbool operator|(vbool a, vbool c) { return {a.b || c.b}; }
  friend vbool operator!(vbool a) { return {!a.b}; }
  friend vbool and_not(vbool a, vbool c) { return {a.b && !c.b}; }
  friend bool any(vbool a) { return a.b; }
  friend bool all(vbool a) { return a.b; }
  friend bool none(vbool a) { return !a.b; }
  static vbool all_true() { return {true}; }
};

template <>
struct vint<1> {
  std::int32_t i;
  vint() = default;
  vint(std::int32_t x) : i(x) {}
  // Wrapping modulo 2^32 as the SIMD widths do, not signed overflow (undefined behaviour).
  friend vint operator+(vint a, vint c) { return {std::int32_t(std::uint32_t(a.i) + std::uint32_t(c.i))}; }
  friend vint operator-(vint a, vint c) { return {std::int32_t(std::uint32_t(a.i) - std::uint32_t(c.i))}; }
  friend vint operator*(vint a, vint c) { return {std::int32_t(std::uint32_t(a.i) * std::uint32_t(c.i))}; }
  friend vint operator&(vint a, vint c) { return {a.i & c.i}; }
  friend vint operator|(vint a, vint c) { return {a.i | c.i}; }
  friend vint operator^(vint a, vint c) { return {a.i ^ c.i}; }
  // Counts 0 .. 31; C++20 shifts a negative value as two's complement, >> arithmetically.
  friend vint operator<<(vint a, vint n) { return {std::int32_t(std::uint32_t(a.i) << n.i)}; }
  friend vint operator<<(vint a, int n) { return {std::int32_t(std::uint32_t(a.i) << n)}; }
  friend vint operator>>(vint a, vint n) { return {a.i >> n.i}; }
  friend vbool<1> operator<(vint a, vint c) { return {a.i < c.i}; }
  friend vbool<1> operator==(vint a, vint c) { return {a.i == c.i}; }
  friend vint min(vint a, vint c) { return {a.i < c.i ? a.i : c.i}; }
  friend vint max(vint a, vint c) { return {a.i > c.i ? a.i : c.i}; }
  friend vint select(vbool<1> m, vint a, vint c) { return m.b ? a : c; }
  static vint load(const std::int32_t* p) { return {*p}; }
  void store(std::int32_t* p) const { *p = i; }
};

template <>
struct vfloat<1> {
  float f;
  static constexpr int width = 1;
  vfloat() = default;
  vfloat(float x) : f(x) {}
  static vfloat load(const float* p) { return {*p}; }
  void store(float* p) const { *p = f; }
  friend vfloat operator+(vfloat a, vfloat c) { return {a.f + c.f}; }
  friend vfloat operator-(vfloat a, vfloat c) { return {a.f - c.f}; }
  friend vfloat operator*(vfloat a, vfloat c) { return {a.f * c.f}; }
  friend vfloat operator/(vfloat a, vfloat c) { return {a.f / c.f}; }
  friend vbool<1> operator<(vfloat a, vfloat c) { return {a.f < c.f}; }
  friend vbool<1> operator>(vfloat a, vfloat c) { return {a.f > c.f}; }
  friend vbool<1> operator>=(vfloat a, vfloat c) { return {a.f >= c.f}; }
  friend vbool<1> operator!=(vfloat a, vfloat c) { return {a.f != c.f}; }
  // min/max return the second operand when either is NaN, as minps/maxps do.
  friend vfloat min(vfloat a, vfloat c) { return {a.f < c.f ? a.f : c.f}; }
  friend vfloat max(vfloat a, vfloat c) { return {a.f > c.f ? a.f : c.f}; }
  friend vfloat abs(vfloat a) { return {std::fabs(a.f)}; }
  friend vfloat floor(vfloat a) { return {std::floor(a.f)}; }
  friend vfloat ceil(vfloat a) { return {std::ceil(a.f)}; }
  friend vfloat select(vbool<1> m, vfloat a, vfloat c) { return m.b ? a : c; }
  // Truncation; out of range and NaN give INT32_MIN, as cvttps2dq does.
  friend vint<1> to_int(vfloat a) {
    return {a.f >= -2147483648.0f && a.f < 2147483648.0f ? static_cast<std::int32_t>(a.f) : INT32_MIN};
  }
};
inline vfloat<1> to_float(vint<1> a) { return {static_cast<float>(a.i)}; }
inline vint<1> to_int(vbool<1> m) { return {m.b ? -1 : 0}; }

inline constexpr int kDoubleWidth = 1;

template <>
struct vboold<1> {
  bool b;
  friend vboold operator&(vboold a, vboold c) { return {a.b && c.b}; }
  friend vboold operator|(vboold a, vboold c) { return {a.b || c.b}; }
  friend vboold operator!(vboold a) { return {!a.b}; }
  friend bool any(vboold a) { return a.b; }
};

template <>
struct vdouble<1> {
  double d;
  vdouble() = default;
  vdouble(double x) : d(x) {}
  static vdouble load(const float* p) { return {double(*p)}; }
  void store(float* p) const { *p = float(d); }
  static vdouble load(const double* p) { return {*p}; }
  void store(double* p) const { *p = d; }
  friend vdouble operator+(vdouble a, vdouble c) { return {a.d + c.d}; }
  friend vdouble operator-(vdouble a, vdouble c) { return {a.d - c.d}; }
  friend vdouble operator*(vdouble a, vdouble c) { return {a.d * c.d}; }
  friend vdouble operator/(vdouble a, vdouble c) { return {a.d / c.d}; }
  friend vdouble operator-(vdouble a) { return {-a.d}; }
  friend vboold<1> operator<(vdouble a, vdouble c) { return {a.d < c.d}; }
  friend vboold<1> operator<=(vdouble a, vdouble c) { return {a.d <= c.d}; }
  friend vboold<1> operator>(vdouble a, vdouble c) { return {a.d > c.d}; }
  friend vboold<1> operator>=(vdouble a, vdouble c) { return {a.d >= c.d}; }
  friend vboold<1> operator==(vdouble a, vdouble c) { return {a.d == c.d}; }
  friend vboold<1> operator!=(vdouble a, vdouble c) { return {a.d != c.d}; }
  friend vdouble min(vdouble a, vdouble c) { return {c.d < a.d ? c.d : a.d}; }
  friend vdouble max(vdouble a, vdouble c) { return {a.d < c.d ? c.d : a.d}; }
  friend vdouble abs(vdouble a) { return {std::fabs(a.d)}; }
  friend vdouble floor(vdouble a) { return {std::floor(a.d)}; }
  friend vdouble sqrt(vdouble a) { return {std::sqrt(a.d)}; }
  friend vdouble copysign(vdouble a, vdouble c) { return {std::copysign(a.d, c.d)}; }
  friend vdouble select(vboold<1> m, vdouble a, vdouble c) { return m.b ? a : c; }
};

// base[index] and base[index + 1] of each lane: two horizontally adjacent texels. All lanes load
// (the sampler keeps every index inside the texture).
inline void gather_pairs(const float* base, vint<1> index, vfloat<1>& first, vfloat<1>& second) {
  first = base[index.i];
  second = base[index.i + 1];
}
// The compute ceiling's stand-in for gather_pairs: first and second as if read at index, with no
// memory access. An empty asm the compiler cannot see through keeps the index computed and the
// taps opaque, so nothing of the bilinear arithmetic is folded or hoisted (zero instructions).
inline void register_pairs(vint<1> index, vfloat<1>& first, vfloat<1>& second) {
  asm volatile("" : "+x"(first.f), "+x"(second.f) : "r"(index.i));
}

// base[index] per lane: the min-depth pyramid's reads and its per-level tables.
inline vfloat<1> gather(const float* base, vint<1> index) { return base[index.i]; }
inline vint<1> gather(const std::int32_t* base, vint<1> index) { return base[index.i]; }
inline vfloat<1> sqrt(vfloat<1> a) { return std::sqrt(a.f); }
// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<1> a) { return std::uint32_t(a.i); }
// The smallest lane.
inline std::int32_t reduce_min(vint<1> a) { return a.i; }
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<1> a, std::uint8_t* p) { *p = std::uint8_t(a.i); }
inline vfloat<1> pow2(vint<1> n) { return {std::ldexp(1.0f, n.i)}; }
inline std::uint32_t mask_bits(vbool<1> m) { return m.b ? 1u : 0u; }
inline vfloat<1> expand_load(const float* p, vbool<1> m, vfloat<1> old) { return m.b ? vfloat<1>(*p) : old; }
inline void compress_store(float* p, vbool<1> m, vfloat<1> value) {
  if (m.b) *p = value.f;
}
inline vint<1> expand_load(const std::int32_t* p, vbool<1> m, vint<1> old) { return m.b ? vint<1>(*p) : old; }
inline void compress_store(std::int32_t* p, vbool<1> m, vint<1> value) {
  if (m.b) *p = value.i;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
