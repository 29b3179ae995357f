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
// - vint +, -, * wrap around modulo 2^32; <, min and max are signed.
// - select(m, a, b) is m ? a : b; any, all, none reduce the mask's lanes.
// - reduce_add sums lanes that are non-negative and whose sum fits 32 bits; store_bytes stores
//   lanes in 0..255. gather, gather_pairs and fetch_taps read exactly the texels they name, each
//   index inside the array.
//
// Every header of this folder opens namespace heightmarch::HEIGHTMARCH_ISA_NS, which the
// including translation unit defines (isa_scalar, isa_sse42, ...), so that inline functions
// compiled with one ISA's flags can never be linked into code running on another ISA.
#ifndef HEIGHTMARCH_ISA_NS
#error "define HEIGHTMARCH_ISA_NS before including a simd/ header"
#endif

#include <cstdint>

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W> struct vfloat;
template <int W> struct vint;
template <int W> struct vbool;
template <int D> struct vdouble;
template <int D> struct vboold;

// The four bilinear taps of each lane from a texture of `rows` rows of `stride` texels: t00 at
// (ix, iy), t10 one texel right, t01 one row down, t11 both. This default reads them with two
// gather_pairs (the ISA's); an ISA header may overload it for its own width with a faster path
// (vfloat16_avx512.hpp), which must read the very same texels.
template <int W>
inline void fetch_taps(const float* texels, std::int32_t stride, std::int32_t rows, vint<W> ix, vint<W> iy,
                       vfloat<W>& t00, vfloat<W>& t10, vfloat<W>& t01, vfloat<W>& t11) {
  (void)rows;
  const vint<W> index = iy * vint<W>(stride) + ix;
  gather_pairs(texels, index, t00, t10);
  gather_pairs(texels + stride, index, t01, t11);
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
