#pragma once
// The packet types of the translation unit's ISA, what every kernel header includes: the ISA's
// packet header of this folder, which the unit names in HEIGHTMARCH_ISA_HEADER as it names its
// namespace in HEIGHTMARCH_ISA_NS, and where the ISA keeps two packets in flight
// (HEIGHTMARCH_PAIR_OF: its native width) their pair, packet_pair.hpp. Each ISA's unit is
// generated from src/isa/kernels.cpp.in.
#ifndef HEIGHTMARCH_ISA_HEADER
#error \
    "define HEIGHTMARCH_ISA_HEADER (the ISA's packet header, e.g. \"simd/vfloat8_avx2.hpp\") before including a kernel header"
#endif
#include HEIGHTMARCH_ISA_HEADER
#ifdef HEIGHTMARCH_PAIR_OF
#include "simd/packet_pair.hpp"
#endif
