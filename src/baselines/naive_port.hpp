#pragma once
// What a user would write instead: LearnOpenGL's POM shader ported line by line to scalar C++
// with GLM, a plain GL_LINEAR/REPEAT texture() and no packets. Compiled with the project's
// normal flags (no ISA flags), parallel over the same tiles with TBB.
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/rays.hpp"
#include "kernels/kernel_abi.hpp"

namespace heightmarch {

// Traces every ray of the batch with the tutorial's POM loop (fixed or dynamic layer count).
void naive_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
               HitBuffers& hits);

// A kernel of the dispatch boundary's signature over the batch's tiles (TBB), writing every hit:
// the ports' and the structured Highway POM's loop.
void trace_tiles(TraceRangeFn kernel, const KernelTexture& texture, const KernelParams& params,
                 const RayBatch& rays, HitBuffers& hits);

// The same port vectorised by the compiler over rays (autovec_port.hpp), built with the ISA's
// flags, over the same tiles. Same u, v and samples as naive_pom. Throws InputError when the CPU
// lacks the ISA.
void autovec_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
                 Isa isa, HitBuffers& hits);

// Whether the port written with Google Highway (highway_port.cpp) runs at the ISA: this build has
// Highway, which compiled the ISA's Highway target (cmake/isa_list.cmake), and the CPU runs it.
bool highway_port_runs(Isa isa);

// The same port written with Google Highway, at the ISA's Highway target, over the same tiles.
// Same samples as naive_pom, u and v within rounding. Throws InputError where it does not run.
void highway_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
                 Isa isa, HitBuffers& hits);

}  // namespace heightmarch
