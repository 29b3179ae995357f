#pragma once
// The options trace, glsl and the other commands share: what to trace, how, and where to.
#include <string>
#include <vector>

#include "cli/options.hpp"
#include "heightmarch/experiment.hpp"

namespace heightmarch::cli {

std::vector<OptionSpec> scene_option_specs();      // heightmap, res, seed, convention, view, size, rays, tile
std::vector<OptionSpec> technique_option_specs();  // technique, layers, refine, scale, wrap, discard, light
std::vector<OptionSpec> run_option_specs();        // threads, out, json
std::vector<OptionSpec> trace_option_specs();      // all three: what trace and glsl share

Scene load_scene(const Options& options);
TechniqueParams technique_params(const Options& options);
int thread_count(const Options& options);  // --threads, 0 = all cores

}  // namespace heightmarch::cli
