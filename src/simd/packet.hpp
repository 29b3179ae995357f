#pragma once
// Packet types vfloat<W>, vint<W>, vbool<W>: one ray per lane. Each ISA's header specialises
// them for its width; the kernels are written once against this interface.
//
// vdouble<D>, vboold<D>: D lanes of double (D = kDoubleWidth, the ISA's register of doubles),
// for the exact reference's solve in double (src/exact/cell_quadratic.hpp). Only what that
// needs; each op rounds as the scalar double op does (IEEE, no contraction), min and max pick
// as std::min and std::max do (the first operand on NaN or equal values), so a template over
// the number type gives the same bits at T = double and T = vdouble<D>.
//
// The contract of every width, width 1 on any architecture included, lane by lane (checked op
// by op on random lanes with NaN, infinities and signed zeros at every ISA of the list by
// tests/packet_ops_test.cpp):
// - +, -, *, /, sqrt round as the scalar IEEE op (no contraction, no flush of denormals); a NaN
//   result is some NaN, its sign and payload unspecified. floor and ceil keep the sign of zero
//   (ceil(-0.5) = -0), abs clears the sign bit (of a NaN too).
// - <, >, >= are ordered (false when a lane is NaN), != is unordered (true).
// - min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b, as minps and maxps pick: the second
//   operand when either is NaN or both are equal (min(+0, -0) = -0). vdouble's pick as
//   std::min and std::max (the first operand).
// - to_int truncates toward zero; NaN and values outside int32's range give INT32_MIN, as x86's
//   cvttps2dq does (the sampler's wrap relies on it: INT32_MIN & (size - 1) is texel 0, and a
//   clamp takes it to 0). Width 1 gives INT32_MIN too, whatever the CPU's own conversion does.
// - vint +, -, * wrap around modulo 2^32; <, ==, min and max are signed; &, |, ^ act on the
//   bits; a << n and a >> n shift each lane by its own count n in 0 .. 31 (>> arithmetic, << as
//   on uint32), a << k every lane by one count k in 0 .. 31. to_float(vint) rounds to nearest
//   (exact below 2^24); to_int(vbool) is -1 where true, 0 where false (both namespace functions,
//   not friends: argument-dependent lookup of a vint or vbool argument finds them).
// - and_not(m, n) is m & !n.
// - select(m, a, b) is m ? a : b; any, all, none reduce the mask's lanes.
// - reduce_add sums lanes that are non-negative and whose sum fits 32 bits; reduce_min is the
//   smallest lane; store_bytes stores lanes in 0..255. gather, gather_pairs and fetch_taps read
//   exactly the texels they name, each index inside the array; lookup(table, index) is
//   table.values[index] for an index in 0..15.
// - mask_bits(m) has bit l set for each true lane l. expand_load(p, m, old) gives the true lanes
//   p[0], p[1], ... in lane order and keeps old in the others; p[0 .. W - 1] must be readable.
//   compress_store(p, m, value) stores the true lanes' values to p[0], p[1], ... in lane order
//   and may write anything to the rest of p[0 .. W - 1]. Both move float and int32 lanes. scatter(base,
//   index, m, value) stores each true lane's value to base[index] (the true lanes' indices distinct) and
//   nothing else. These move rays in and out of a walk's lanes (src/kernels/pyramid_walk.hpp). pow2(n) is 2^n
//   exactly for n in -126 .. 127.
//
// Every header of this folder opens namespace heightmarch::HEIGHTMARCH_ISA_NS, which the
// including translation unit defines (isa_scalar, isa_sse42, ...), so that inline functions
// compiled with one ISA's flags can never be linked into code running on another ISA.
#ifndef HEIGHTMARCH_ISA_NS
#error "define HEIGHTMARCH_ISA_NS before including a simd/ header"
#endif

#include <bit>
#include <cstdint>

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W>
struct vfloat;
template <int W>
struct vint;
template <int W>
struct vbool;
template <int D>
struct vdouble;
template <int D>
struct vboold;

// The four bilinear taps of each lane from a texture of `rows` rows of `stride` texels: t00 at
// (ix, iy), t10 one texel right, t01 one row down, t11 both. This default reads them with two
// gather_pairs (the ISA's); an ISA header may overload it for its own width with a faster path
// (vfloat8_avx2.hpp, vfloat16_avx512.hpp), which must read the very same texels.
template <int W>
inline void fetch_taps(const float* texels, std::int32_t stride, std::int32_t rows, vint<W> ix, vint<W> iy,
                       vfloat<W>& t00, vfloat<W>& t10, vfloat<W>& t01, vfloat<W>& t11) {
  (void)rows;
  const vint<W> index = iy * vint<W>(stride) + ix;
  gather_pairs(texels, index, t00, t10);
  gather_pairs(texels + stride, index, t01, t11);
}

// A table of up to 16 values that lanes look up by index (lookup()): the pyramid walk's
// constants per level.
template <class T>
struct Table16 {
  alignas(64) T values[16] = {};
};

// table.values[index] per lane, 0 <= index < 16. These defaults gather; an ISA header may
// overload them for its own width with register permutes.
template <int W>
inline vint<W> lookup(const Table16<std::int32_t>& table, vint<W> index) {
  return gather(table.values, index);
}
template <int W>
inline vfloat<W> lookup(const Table16<float>& table, vint<W> index) {
  return gather(table.values, index);
}

// scatter() through memory, lane by lane; an ISA header may overload it with the ISA's scatter.
template <int W, class T, class V>
inline void scatter_lanes(T* base, vint<W> index, vbool<W> mask, V value) {
  alignas(64) std::int32_t at[W];
  alignas(64) T lanes[W];
  index.store(at);
  value.store(lanes);
  for (std::uint32_t bits = mask_bits(mask); bits != 0; bits &= bits - 1) {
    const int lane = std::countr_zero(bits);
    base[at[lane]] = lanes[lane];
  }
}
template <int W>
inline void scatter(float* base, vint<W> index, vbool<W> mask, vfloat<W> value) {
  scatter_lanes<W>(base, index, mask, value);
}
template <int W>
inline void scatter(std::int32_t* base, vint<W> index, vbool<W> mask, vint<W> value) {
  scatter_lanes<W>(base, index, mask, value);
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
