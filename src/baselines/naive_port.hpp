#pragma once
// What a user would write instead: LearnOpenGL's POM shader ported line by line to scalar C++
// with GLM, a plain GL_LINEAR/REPEAT texture() and no packets. Compiled with the project's
// normal flags (no ISA flags), parallel over the same tiles with TBB.
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/rays.hpp"

namespace heightmarch {

// Traces every ray of the batch with the tutorial's POM loop (fixed or dynamic layer count).
void naive_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
               HitBuffers& hits);

// The same port vectorised by the compiler over rays (autovec_port.hpp), built with the ISA's
// flags, over the same tiles. Same u, v and samples as naive_pom. Throws InputError when the CPU
// lacks the ISA.
void autovec_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale, Isa isa,
                 HitBuffers& hits);

}  // namespace heightmarch
