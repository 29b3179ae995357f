#pragma once
// The benchmarks of heightmarch-bench and the scenes they share.
#include <string>
#include <vector>

#include "heightmarch/isa.hpp"

namespace heightmarch::bench {

struct BenchConfig {
  int view_size = 1024;
  int resolution = 512;
  std::vector<std::string> heightfields = {"bricks", "terrain"};  // builtin names or depth map files
  std::vector<std::string> layer_specs = {"4", "8", "16", "32", "64", "8-32"};
  double min_time = 0.2;  // seconds per benchmark
  std::vector<int> threads;  // empty: 1 and all cores
  std::vector<Isa> isas;     // empty: every ISA the CPU runs
  int glsl_threads = 0;      // llvmpipe threads of BM_GLSL (one count per process); 0: the most of `threads`
};

// BM_Trace, BM_SamplerRoofline and BM_NaivePort for every configuration.
void register_benchmarks(const BenchConfig& config);

}  // namespace heightmarch::bench
