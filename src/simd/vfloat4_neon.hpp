#pragma once
// Width 4: Advanced SIMD (NEON), the AArch64 baseline. Where NEON's own instructions differ from
// the contract of packet.hpp (x86's picks), the contract is emulated: fmin/fmax return NaN and
// order -0 below +0, so min and max compare and select; fcvtzs saturates and takes NaN to 0, so
// to_int puts INT32_MIN in every lane out of range. NEON has no gather: lanes are loaded one by
// one, texel pairs with one 64-bit load each; tbl, NEON's byte-table shuffle, moves lanes
// (expand, compress) and looks up the 16-entry tables.
#include <arm_neon.h>

#include <cstring>

#include "simd/lane_shuffles4.hpp"
#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<4> {
  uint32x4_t m;  // all-ones lanes are true
  friend vbool operator&(vbool a, vbool c) { return {vandq_u32(a.m, c.m)}; }
  friend vbool operator|(vbool a, vbool c) { return {vorrq_u32(a.m, c.m)}; }
  friend vbool operator!(vbool a) { return {vmvnq_u32(a.m)}; }
  friend vbool and_not(vbool a, vbool c) { return {vbicq_u32(a.m, c.m)}; }
  friend bool any(vbool a) { return vmaxvq_u32(a.m) != 0; }
  friend bool all(vbool a) { return vminvq_u32(a.m) != 0; }
  friend bool none(vbool a) { return vmaxvq_u32(a.m) == 0; }
  static vbool all_true() { return {vdupq_n_u32(~0u)}; }
};

template <>
struct vint<4> {
  int32x4_t i;
  vint() = default;
  vint(int32x4_t x) : i(x) {}
  vint(std::int32_t x) : i(vdupq_n_s32(x)) {}
  friend vint operator+(vint a, vint c) { return vaddq_s32(a.i, c.i); }
  friend vint operator-(vint a, vint c) { return vsubq_s32(a.i, c.i); }
  friend vint operator*(vint a, vint c) { return vmulq_s32(a.i, c.i); }
  friend vint operator&(vint a, vint c) { return vandq_s32(a.i, c.i); }
  friend vint operator|(vint a, vint c) { return vorrq_s32(a.i, c.i); }
  friend vint operator^(vint a, vint c) { return veorq_s32(a.i, c.i); }
  // sshl shifts each lane by its own signed count: left where positive, arithmetic right where negative.
  friend vint operator<<(vint a, vint n) { return vshlq_s32(a.i, n.i); }
  friend vint operator<<(vint a, int n) { return vshlq_s32(a.i, vdupq_n_s32(n)); }
  friend vint operator>>(vint a, vint n) { return vshlq_s32(a.i, vnegq_s32(n.i)); }
  friend vbool<4> operator<(vint a, vint c) { return {vcltq_s32(a.i, c.i)}; }
  friend vbool<4> operator==(vint a, vint c) { return {vceqq_s32(a.i, c.i)}; }
  friend vint min(vint a, vint c) { return vminq_s32(a.i, c.i); }
  friend vint max(vint a, vint c) { return vmaxq_s32(a.i, c.i); }
  friend vint select(vbool<4> m, vint a, vint c) { return vbslq_s32(m.m, a.i, c.i); }
  static vint load(const std::int32_t* p) { return vld1q_s32(p); }
  void store(std::int32_t* p) const { vst1q_s32(p, i); }
};

template <>
struct vfloat<4> {
  float32x4_t f;
  static constexpr int width = 4;
  vfloat() = default;
  vfloat(float32x4_t x) : f(x) {}
  vfloat(float x) : f(vdupq_n_f32(x)) {}
  static vfloat load(const float* p) { return vld1q_f32(p); }
  void store(float* p) const { vst1q_f32(p, f); }
  friend vfloat operator+(vfloat a, vfloat c) { return vaddq_f32(a.f, c.f); }
  friend vfloat operator-(vfloat a, vfloat c) { return vsubq_f32(a.f, c.f); }
  friend vfloat operator*(vfloat a, vfloat c) { return vmulq_f32(a.f, c.f); }
  friend vfloat operator/(vfloat a, vfloat c) { return vdivq_f32(a.f, c.f); }
  friend vbool<4> operator<(vfloat a, vfloat c) { return {vcltq_f32(a.f, c.f)}; }
  friend vbool<4> operator>(vfloat a, vfloat c) { return {vcgtq_f32(a.f, c.f)}; }
  friend vbool<4> operator>=(vfloat a, vfloat c) { return {vcgeq_f32(a.f, c.f)}; }
  friend vbool<4> operator!=(vfloat a, vfloat c) { return {vmvnq_u32(vceqq_f32(a.f, c.f))}; }
  // minps/maxps's pick (the second operand on NaN or equal values), not fmin/fmax's.
  friend vfloat min(vfloat a, vfloat c) { return vbslq_f32(vcltq_f32(a.f, c.f), a.f, c.f); }
  friend vfloat max(vfloat a, vfloat c) { return vbslq_f32(vcgtq_f32(a.f, c.f), a.f, c.f); }
  friend vfloat abs(vfloat a) { return vabsq_f32(a.f); }
  friend vfloat floor(vfloat a) { return vrndmq_f32(a.f); }
  friend vfloat ceil(vfloat a) { return vrndpq_f32(a.f); }
  friend vfloat select(vbool<4> m, vfloat a, vfloat c) { return vbslq_f32(m.m, a.f, c.f); }
  // Truncation, and INT32_MIN where |a| < 2^31 fails (out of range, NaN), as cvttps2dq gives;
  // -2^31 itself converts to INT32_MIN either way.
  friend vint<4> to_int(vfloat a) {
    return vbslq_s32(vcaltq_f32(a.f, vdupq_n_f32(2147483648.0f)), vcvtq_s32_f32(a.f), vdupq_n_s32(INT32_MIN));
  }
};
inline vfloat<4> to_float(vint<4> a) { return vcvtq_f32_s32(a.i); }
inline vint<4> to_int(vbool<4> m) { return vreinterpretq_s32_u32(m.m); }

inline constexpr int kDoubleWidth = 2;

template <>
struct vboold<2> {
  uint64x2_t m;  // all-ones lanes are true
  friend vboold operator&(vboold a, vboold c) { return {vandq_u64(a.m, c.m)}; }
  friend vboold operator|(vboold a, vboold c) { return {vorrq_u64(a.m, c.m)}; }
  friend vboold operator!(vboold a) { return {vreinterpretq_u64_u32(vmvnq_u32(vreinterpretq_u32_u64(a.m)))}; }
  friend bool any(vboold a) { return vmaxvq_u32(vreinterpretq_u32_u64(a.m)) != 0; }
};

template <>
struct vdouble<2> {
  float64x2_t d;
  vdouble() = default;
  vdouble(float64x2_t x) : d(x) {}
  vdouble(double x) : d(vdupq_n_f64(x)) {}
  static vdouble load(const float* p) { return vcvt_f64_f32(vld1_f32(p)); }
  void store(float* p) const { vst1_f32(p, vcvt_f32_f64(d)); }
  static vdouble load(const double* p) { return vld1q_f64(p); }
  void store(double* p) const { vst1q_f64(p, d); }
  friend vdouble operator+(vdouble a, vdouble c) { return vaddq_f64(a.d, c.d); }
  friend vdouble operator-(vdouble a, vdouble c) { return vsubq_f64(a.d, c.d); }
  friend vdouble operator*(vdouble a, vdouble c) { return vmulq_f64(a.d, c.d); }
  friend vdouble operator/(vdouble a, vdouble c) { return vdivq_f64(a.d, c.d); }
  friend vdouble operator-(vdouble a) { return vnegq_f64(a.d); }
  friend vboold<2> operator<(vdouble a, vdouble c) { return {vcltq_f64(a.d, c.d)}; }
  friend vboold<2> operator<=(vdouble a, vdouble c) { return {vcleq_f64(a.d, c.d)}; }
  friend vboold<2> operator>(vdouble a, vdouble c) { return {vcgtq_f64(a.d, c.d)}; }
  friend vboold<2> operator>=(vdouble a, vdouble c) { return {vcgeq_f64(a.d, c.d)}; }
  friend vboold<2> operator==(vdouble a, vdouble c) { return {vceqq_f64(a.d, c.d)}; }
  friend vboold<2> operator!=(vdouble a, vdouble c) { return !vboold<2>{vceqq_f64(a.d, c.d)}; }
  // std::min and std::max's pick (the first operand on NaN or equal values).
  friend vdouble min(vdouble a, vdouble c) { return vbslq_f64(vcltq_f64(c.d, a.d), c.d, a.d); }
  friend vdouble max(vdouble a, vdouble c) { return vbslq_f64(vcltq_f64(a.d, c.d), c.d, a.d); }
  friend vdouble abs(vdouble a) { return vabsq_f64(a.d); }
  friend vdouble floor(vdouble a) { return vrndmq_f64(a.d); }
  friend vdouble sqrt(vdouble a) { return vsqrtq_f64(a.d); }
  friend vdouble copysign(vdouble a, vdouble c) {
    return vbslq_f64(vdupq_n_u64(0x8000000000000000ull), c.d, a.d);  // the sign bit of c, the rest of a
  }
  friend vdouble select(vboold<2> m, vdouble a, vdouble c) { return vbslq_f64(m.m, a.d, c.d); }
};

// base[index] and base[index + 1] of each lane: one 64-bit load per lane fetches both texels
// (they need only 4-byte alignment), then the pairs are deinterleaved.
inline void gather_pairs(const float* base, vint<4> index, vfloat<4>& first, vfloat<4>& second) {
  const float32x4_t p01 = vcombine_f32(vld1_f32(base + vgetq_lane_s32(index.i, 0)),
                                       vld1_f32(base + vgetq_lane_s32(index.i, 1)));  // a0 b0 a1 b1
  const float32x4_t p23 = vcombine_f32(vld1_f32(base + vgetq_lane_s32(index.i, 2)),
                                       vld1_f32(base + vgetq_lane_s32(index.i, 3)));  // a2 b2 a3 b3
  first = vuzp1q_f32(p01, p23);
  second = vuzp2q_f32(p01, p23);
}
// The compute ceiling's stand-in for gather_pairs: first and second as if read at index, with no
// memory access. An empty asm the compiler cannot see through keeps the index computed and the
// taps opaque, so nothing of the bilinear arithmetic is folded or hoisted (zero instructions).
inline void register_pairs(vint<4> index, vfloat<4>& first, vfloat<4>& second) {
  asm volatile("" : "+w"(first.f), "+w"(second.f) : "w"(index.i));
}

// base[index] per lane: one lane load each.
inline vfloat<4> gather(const float* base, vint<4> index) {
  float32x4_t r = vld1q_dup_f32(base + vgetq_lane_s32(index.i, 0));
  r = vld1q_lane_f32(base + vgetq_lane_s32(index.i, 1), r, 1);
  r = vld1q_lane_f32(base + vgetq_lane_s32(index.i, 2), r, 2);
  return vld1q_lane_f32(base + vgetq_lane_s32(index.i, 3), r, 3);
}
inline vint<4> gather(const std::int32_t* base, vint<4> index) {
  int32x4_t r = vld1q_dup_s32(base + vgetq_lane_s32(index.i, 0));
  r = vld1q_lane_s32(base + vgetq_lane_s32(index.i, 1), r, 1);
  r = vld1q_lane_s32(base + vgetq_lane_s32(index.i, 2), r, 2);
  return vld1q_lane_s32(base + vgetq_lane_s32(index.i, 3), r, 3);
}

// lookup() (packet.hpp) with one tbl over the table's 64 bytes: lane l takes bytes 4 index .. 4
// index + 3.
inline uint8x16_t lookup_bytes(const void* table, vint<4> index) {
  const uint8x16x4_t bytes = vld1q_u8_x4(static_cast<const std::uint8_t*>(table));
  const uint32x4_t control =
      vmlaq_n_u32(vdupq_n_u32(0x03020100u), vreinterpretq_u32_s32(index.i), 0x04040404u);
  return vqtbl4q_u8(bytes, vreinterpretq_u8_u32(control));
}
inline vfloat<4> lookup(const Table16<float>& table, vint<4> index) {
  return vreinterpretq_f32_u8(lookup_bytes(table.values, index));
}
inline vint<4> lookup(const Table16<std::int32_t>& table, vint<4> index) {
  return vreinterpretq_s32_u8(lookup_bytes(table.values, index));
}

// The sum of the lanes (non-negative counts whose sum fits 32 bits).
inline std::uint32_t reduce_add(vint<4> a) { return std::uint32_t(vaddvq_s32(a.i)); }
// The smallest lane.
inline std::int32_t reduce_min(vint<4> a) { return vminvq_s32(a.i); }
// Each lane's value (0 to 255) as one byte, to p[0] .. p[W - 1].
inline void store_bytes(vint<4> a, std::uint8_t* p) {
  const uint16x4_t words = vmovn_u32(vreinterpretq_u32_s32(a.i));
  const std::uint32_t bytes = vget_lane_u32(vreinterpret_u32_u8(vmovn_u16(vcombine_u16(words, words))), 0);
  std::memcpy(p, &bytes, sizeof bytes);
}
inline vfloat<4> sqrt(vfloat<4> a) { return vsqrtq_f32(a.f); }

// 2^n built from its exponent bits.
inline vfloat<4> pow2(vint<4> n) {
  return vreinterpretq_f32_s32(vshlq_n_s32(vaddq_s32(n.i, vdupq_n_s32(127)), 23));
}
// Each lane's bit, summed across the lanes.
inline std::uint32_t mask_bits(vbool<4> m) {
  static constexpr std::uint32_t kBits[4] = {1, 2, 4, 8};
  return vaddvq_u32(vandq_u32(m.m, vld1q_u32(kBits)));
}

// expand_load() and compress_store() (packet.hpp) with one tbl (lane_shuffles4.hpp).
inline uint8x16_t expand_lanes(uint8x16_t loaded, vbool<4> m, uint8x16_t old) {
  const uint8x16_t spread = vqtbl1q_u8(loaded, vld1q_u8(kLaneShuffles4.expand[mask_bits(m)]));
  return vbslq_u8(vreinterpretq_u8_u32(m.m), spread, old);
}
inline uint8x16_t compress_lanes(uint8x16_t value, vbool<4> m) {
  return vqtbl1q_u8(value, vld1q_u8(kLaneShuffles4.compress[mask_bits(m)]));
}
inline vfloat<4> expand_load(const float* p, vbool<4> m, vfloat<4> old) {
  return vreinterpretq_f32_u8(
      expand_lanes(vreinterpretq_u8_f32(vld1q_f32(p)), m, vreinterpretq_u8_f32(old.f)));
}
inline vint<4> expand_load(const std::int32_t* p, vbool<4> m, vint<4> old) {
  return vreinterpretq_s32_u8(
      expand_lanes(vreinterpretq_u8_s32(vld1q_s32(p)), m, vreinterpretq_u8_s32(old.i)));
}
inline void compress_store(float* p, vbool<4> m, vfloat<4> value) {
  vst1q_f32(p, vreinterpretq_f32_u8(compress_lanes(vreinterpretq_u8_f32(value.f), m)));
}
inline void compress_store(std::int32_t* p, vbool<4> m, vint<4> value) {
  vst1q_s32(p, vreinterpretq_s32_u8(compress_lanes(vreinterpretq_u8_s32(value.i), m)));
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
