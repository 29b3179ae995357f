#pragma once
// The kernels written with Google Highway, of the dispatch boundary's signature: the port of the
// tutorial's POM (highway_port.cpp; naive_port.hpp runs it over a batch) and the hand-written
// POM's structure on Highway's ops (highway_structured.cpp; HighwayStructuredPom runs it).
#include "kernels/kernel_abi.hpp"

namespace heightmarch {

// Where the ISA's Highway target (cmake/isa_list.cmake) is in Highway's dispatch tables; -1
// where it does not run: a target Highway did not compile, or one the CPU lacks.
int highway_dispatch_entry(Isa isa);

// The kernels at that entry; null where it does not run (a build without Highway included).
TraceRangeFn highway_kernel(Isa isa);
TraceRangeFn highway_structured_kernel(Isa isa);

}  // namespace heightmarch
