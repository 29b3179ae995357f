#pragma once
// Packet types vfloat<W>, vint<W>, vbool<W>: one ray per lane. Each ISA's header specialises
// them for its width; the kernels are written once against this interface.
//
// Every header of this folder opens namespace heightmarch::HEIGHTMARCH_ISA_NS, which the
// including translation unit defines (isa_scalar, isa_sse42, ...), so that inline functions
// compiled with one ISA's flags can never be linked into code running on another ISA.
#ifndef HEIGHTMARCH_ISA_NS
#error "define HEIGHTMARCH_ISA_NS before including a heightmarch/simd header"
#endif

#include <cstdint>

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <int W> struct vfloat;
template <int W> struct vint;
template <int W> struct vbool;

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
