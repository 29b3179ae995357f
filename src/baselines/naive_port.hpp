#pragma once
// What a user would write instead: LearnOpenGL's POM shader ported line by line to scalar C++
// with GLM, a plain GL_LINEAR/REPEAT texture() and no packets. Compiled with the project's
// normal flags (no ISA flags), parallel over the same tiles with TBB.
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"

namespace heightmarch {

// Traces every ray of the batch with the tutorial's POM loop (fixed or dynamic layer count).
void naive_pom(const DepthMap& map, const RayBatch& rays, float min_layers, float max_layers, float scale,
               HitBuffers& hits);

}  // namespace heightmarch
