#pragma once
// The port of the tutorial's POM written with Google Highway (highway_port.cpp), as a kernel of
// the dispatch boundary's signature; naive_port.hpp runs it over a batch.
#include "kernels/kernel_abi.hpp"

namespace heightmarch {

// The entry of Highway's dispatch table for the ISA's Highway target (cmake/isa_list.cmake);
// null where it does not run: a build without Highway, a target Highway did not compile, or
// one the CPU lacks.
TraceRangeFn highway_kernel(Isa isa);

}  // namespace heightmarch
