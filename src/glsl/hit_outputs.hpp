#pragma once
// The GLSL harness's side of the hit list (heightmarch/hits.hpp): what a technique's GLSL function
// returns (struct Hit), the fragment outputs it is stored to and their read-back. Every output a
// technique writes (the list's hit and optional rows) is drawn as a float, four to an RGBA32F
// colour attachment, in the list's order; `discarded` follows from the uv on the read-back.
#include <cstddef>
#include <string>
#include <vector>

#include "heightmarch/hits.hpp"

namespace heightmarch {

// struct Hit (one float per drawn output), Hit hitAt(vec2 uv, float depth) (the others at their
// initial values), the attachments' outputs and void storeHit(Hit hit).
std::string hit_outputs_glsl();

// RGBA32F colour attachments the harness draws into.
int hit_output_attachments();

// Where the samples lie in the attachments (attachment, component): a NaN left there by a clear is
// a ray whose fragment was discarded.
std::pair<int, int> samples_output();

// Fills `rays` rays of hits from the attachments' pixels (RGBA floats, batch order); discard: the
// tutorial's discard of a final uv outside [0,1]^2. samples_known: no ray drew -1 samples.
void read_hit_outputs(const std::vector<std::vector<float>>& attachments, std::size_t rays, bool discard,
                      HitBuffers& hits, bool& samples_known);

}  // namespace heightmarch
