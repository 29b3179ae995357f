#pragma once
// Two packets of the ISA's native width marched together as one of twice the width, so each
// loop iteration issues two independent sets of gathers (more in flight to hide their latency).
// Every operation applies to both halves; each lane's result is that of the native width.
// The including translation unit names the native width in HEIGHTMARCH_PAIR_OF after including
// its ISA's header (measured: two in flight beat one by 17-36% on AVX-512; four lost to register
// pressure).
#ifndef HEIGHTMARCH_PAIR_OF
#error "define HEIGHTMARCH_PAIR_OF (the native packet width) before including packet_pair.hpp"
#endif
#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <>
struct vbool<2 * HEIGHTMARCH_PAIR_OF> {
  vbool<HEIGHTMARCH_PAIR_OF> lo, hi;
  friend vbool operator&(vbool a, vbool c) { return {a.lo & c.lo, a.hi & c.hi}; }
  friend vbool operator|(vbool a, vbool c) { return {a.lo | c.lo, a.hi | c.hi}; }
  friend vbool operator!(vbool a) { return {!a.lo, !a.hi}; }
  friend vbool and_not(vbool a, vbool c) { return {and_not(a.lo, c.lo), and_not(a.hi, c.hi)}; }
  friend bool any(vbool a) { return any(a.lo | a.hi); }
  friend bool all(vbool a) { return all(a.lo & a.hi); }
  friend bool none(vbool a) { return none(a.lo | a.hi); }
  static vbool all_true() {
    return {vbool<HEIGHTMARCH_PAIR_OF>::all_true(), vbool<HEIGHTMARCH_PAIR_OF>::all_true()};
  }
};

template <>
struct vint<2 * HEIGHTMARCH_PAIR_OF> {
  vint<HEIGHTMARCH_PAIR_OF> lo, hi;
  vint() = default;
  vint(vint<HEIGHTMARCH_PAIR_OF> l, vint<HEIGHTMARCH_PAIR_OF> h) : lo(l), hi(h) {}
  vint(std::int32_t x) : lo(x), hi(x) {}
  friend vint operator+(vint a, vint c) { return {a.lo + c.lo, a.hi + c.hi}; }
  friend vint operator-(vint a, vint c) { return {a.lo - c.lo, a.hi - c.hi}; }
  friend vint operator*(vint a, vint c) { return {a.lo * c.lo, a.hi * c.hi}; }
  friend vint operator&(vint a, vint c) { return {a.lo & c.lo, a.hi & c.hi}; }
  friend vint operator|(vint a, vint c) { return {a.lo | c.lo, a.hi | c.hi}; }
  friend vint operator^(vint a, vint c) { return {a.lo ^ c.lo, a.hi ^ c.hi}; }
  friend vint operator<<(vint a, vint n) { return {a.lo << n.lo, a.hi << n.hi}; }
  friend vint operator<<(vint a, int n) { return {a.lo << n, a.hi << n}; }
  friend vint operator>>(vint a, vint n) { return {a.lo >> n.lo, a.hi >> n.hi}; }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator<(vint a, vint c) { return {a.lo < c.lo, a.hi < c.hi}; }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator==(vint a, vint c) { return {a.lo == c.lo, a.hi == c.hi}; }
  friend vint min(vint a, vint c) { return {min(a.lo, c.lo), min(a.hi, c.hi)}; }
  friend vint max(vint a, vint c) { return {max(a.lo, c.lo), max(a.hi, c.hi)}; }
  friend vint select(vbool<2 * HEIGHTMARCH_PAIR_OF> m, vint a, vint c) {
    return {select(m.lo, a.lo, c.lo), select(m.hi, a.hi, c.hi)};
  }
  static vint load(const std::int32_t* p) {
    return {vint<HEIGHTMARCH_PAIR_OF>::load(p), vint<HEIGHTMARCH_PAIR_OF>::load(p + HEIGHTMARCH_PAIR_OF)};
  }
  void store(std::int32_t* p) const {
    lo.store(p);
    hi.store(p + HEIGHTMARCH_PAIR_OF);
  }
};

template <>
struct vfloat<2 * HEIGHTMARCH_PAIR_OF> {
  vfloat<HEIGHTMARCH_PAIR_OF> lo, hi;
  static constexpr int width = 2 * HEIGHTMARCH_PAIR_OF;
  vfloat() = default;
  vfloat(vfloat<HEIGHTMARCH_PAIR_OF> l, vfloat<HEIGHTMARCH_PAIR_OF> h) : lo(l), hi(h) {}
  vfloat(float x) : lo(x), hi(x) {}
  static vfloat load(const float* p) {
    return {vfloat<HEIGHTMARCH_PAIR_OF>::load(p), vfloat<HEIGHTMARCH_PAIR_OF>::load(p + HEIGHTMARCH_PAIR_OF)};
  }
  void store(float* p) const {
    lo.store(p);
    hi.store(p + HEIGHTMARCH_PAIR_OF);
  }
  friend vfloat operator+(vfloat a, vfloat c) { return {a.lo + c.lo, a.hi + c.hi}; }
  friend vfloat operator-(vfloat a, vfloat c) { return {a.lo - c.lo, a.hi - c.hi}; }
  friend vfloat operator*(vfloat a, vfloat c) { return {a.lo * c.lo, a.hi * c.hi}; }
  friend vfloat operator/(vfloat a, vfloat c) { return {a.lo / c.lo, a.hi / c.hi}; }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator<(vfloat a, vfloat c) { return {a.lo < c.lo, a.hi < c.hi}; }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator>(vfloat a, vfloat c) { return {a.lo > c.lo, a.hi > c.hi}; }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator>=(vfloat a, vfloat c) {
    return {a.lo >= c.lo, a.hi >= c.hi};
  }
  friend vbool<2 * HEIGHTMARCH_PAIR_OF> operator!=(vfloat a, vfloat c) {
    return {a.lo != c.lo, a.hi != c.hi};
  }
  friend vfloat min(vfloat a, vfloat c) { return {min(a.lo, c.lo), min(a.hi, c.hi)}; }
  friend vfloat max(vfloat a, vfloat c) { return {max(a.lo, c.lo), max(a.hi, c.hi)}; }
  friend vfloat abs(vfloat a) { return {abs(a.lo), abs(a.hi)}; }
  friend vfloat floor(vfloat a) { return {floor(a.lo), floor(a.hi)}; }
  friend vfloat ceil(vfloat a) { return {ceil(a.lo), ceil(a.hi)}; }
  friend vfloat select(vbool<2 * HEIGHTMARCH_PAIR_OF> m, vfloat a, vfloat c) {
    return {select(m.lo, a.lo, c.lo), select(m.hi, a.hi, c.hi)};
  }
  friend vint<2 * HEIGHTMARCH_PAIR_OF> to_int(vfloat a) { return {to_int(a.lo), to_int(a.hi)}; }
};

inline vfloat<2 * HEIGHTMARCH_PAIR_OF> to_float(vint<2 * HEIGHTMARCH_PAIR_OF> a) {
  return {to_float(a.lo), to_float(a.hi)};
}
inline vint<2 * HEIGHTMARCH_PAIR_OF> to_int(vbool<2 * HEIGHTMARCH_PAIR_OF> m) {
  return {to_int(m.lo), to_int(m.hi)};
}

inline void gather_pairs(const float* base, vint<2 * HEIGHTMARCH_PAIR_OF> index,
                         vfloat<2 * HEIGHTMARCH_PAIR_OF>& first, vfloat<2 * HEIGHTMARCH_PAIR_OF>& second) {
  gather_pairs(base, index.lo, first.lo, second.lo);
  gather_pairs(base, index.hi, first.hi, second.hi);
}

// Each half by its own path (a coherent half need not wait for the other).
inline void fetch_taps(const float* texels, std::int32_t stride, std::int32_t rows,
                       vint<2 * HEIGHTMARCH_PAIR_OF> ix, vint<2 * HEIGHTMARCH_PAIR_OF> iy,
                       vfloat<2 * HEIGHTMARCH_PAIR_OF>& t00, vfloat<2 * HEIGHTMARCH_PAIR_OF>& t10,
                       vfloat<2 * HEIGHTMARCH_PAIR_OF>& t01, vfloat<2 * HEIGHTMARCH_PAIR_OF>& t11) {
  fetch_taps(texels, stride, rows, ix.lo, iy.lo, t00.lo, t10.lo, t01.lo, t11.lo);
  fetch_taps(texels, stride, rows, ix.hi, iy.hi, t00.hi, t10.hi, t01.hi, t11.hi);
}

inline void register_pairs(vint<2 * HEIGHTMARCH_PAIR_OF> index, vfloat<2 * HEIGHTMARCH_PAIR_OF>& first,
                           vfloat<2 * HEIGHTMARCH_PAIR_OF>& second) {
  register_pairs(index.lo, first.lo, second.lo);
  register_pairs(index.hi, first.hi, second.hi);
}

inline vfloat<2 * HEIGHTMARCH_PAIR_OF> gather(const float* base, vint<2 * HEIGHTMARCH_PAIR_OF> index) {
  return {gather(base, index.lo), gather(base, index.hi)};
}
inline vint<2 * HEIGHTMARCH_PAIR_OF> gather(const std::int32_t* base, vint<2 * HEIGHTMARCH_PAIR_OF> index) {
  return {gather(base, index.lo), gather(base, index.hi)};
}
inline vint<2 * HEIGHTMARCH_PAIR_OF> lookup(const Table16<std::int32_t>& table,
                                            vint<2 * HEIGHTMARCH_PAIR_OF> index) {
  return {lookup(table, index.lo), lookup(table, index.hi)};
}
inline vfloat<2 * HEIGHTMARCH_PAIR_OF> lookup(const Table16<float>& table,
                                              vint<2 * HEIGHTMARCH_PAIR_OF> index) {
  return {lookup(table, index.lo), lookup(table, index.hi)};
}
inline vfloat<2 * HEIGHTMARCH_PAIR_OF> sqrt(vfloat<2 * HEIGHTMARCH_PAIR_OF> a) {
  return {sqrt(a.lo), sqrt(a.hi)};
}
inline std::uint32_t reduce_add(vint<2 * HEIGHTMARCH_PAIR_OF> a) {
  return reduce_add(a.lo) + reduce_add(a.hi);
}
inline std::int32_t reduce_min(vint<2 * HEIGHTMARCH_PAIR_OF> a) {
  const std::int32_t lo = reduce_min(a.lo), hi = reduce_min(a.hi);
  return lo < hi ? lo : hi;
}
inline void store_bytes(vint<2 * HEIGHTMARCH_PAIR_OF> a, std::uint8_t* p) {
  store_bytes(a.lo, p);
  store_bytes(a.hi, p + HEIGHTMARCH_PAIR_OF);
}
inline vfloat<2 * HEIGHTMARCH_PAIR_OF> pow2(vint<2 * HEIGHTMARCH_PAIR_OF> n) {
  return {pow2(n.lo), pow2(n.hi)};
}
inline std::uint32_t mask_bits(vbool<2 * HEIGHTMARCH_PAIR_OF> m) {
  return mask_bits(m.lo) | mask_bits(m.hi) << HEIGHTMARCH_PAIR_OF;
}
// The high half's lanes take the elements after the low half's.
inline vfloat<2 * HEIGHTMARCH_PAIR_OF> expand_load(const float* p, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                                                   vfloat<2 * HEIGHTMARCH_PAIR_OF> old) {
  return {expand_load(p, m.lo, old.lo), expand_load(p + std::popcount(mask_bits(m.lo)), m.hi, old.hi)};
}
inline vint<2 * HEIGHTMARCH_PAIR_OF> expand_load(const std::int32_t* p, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                                                 vint<2 * HEIGHTMARCH_PAIR_OF> old) {
  return {expand_load(p, m.lo, old.lo), expand_load(p + std::popcount(mask_bits(m.lo)), m.hi, old.hi)};
}
inline void compress_store(float* p, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                           vfloat<2 * HEIGHTMARCH_PAIR_OF> value) {
  compress_store(p, m.lo, value.lo);
  compress_store(p + std::popcount(mask_bits(m.lo)), m.hi, value.hi);
}
inline void compress_store(std::int32_t* p, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                           vint<2 * HEIGHTMARCH_PAIR_OF> value) {
  compress_store(p, m.lo, value.lo);
  compress_store(p + std::popcount(mask_bits(m.lo)), m.hi, value.hi);
}
inline void scatter(float* base, vint<2 * HEIGHTMARCH_PAIR_OF> index, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                    vfloat<2 * HEIGHTMARCH_PAIR_OF> value) {
  scatter(base, index.lo, m.lo, value.lo);
  scatter(base, index.hi, m.hi, value.hi);
}
inline void scatter(std::int32_t* base, vint<2 * HEIGHTMARCH_PAIR_OF> index, vbool<2 * HEIGHTMARCH_PAIR_OF> m,
                    vint<2 * HEIGHTMARCH_PAIR_OF> value) {
  scatter(base, index.lo, m.lo, value.lo);
  scatter(base, index.hi, m.hi, value.hi);
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
