#pragma once
// The benchmarks of heightmarch-bench and the scenes they share.
#include <string>
#include <vector>

#include "heightmarch/isa.hpp"

namespace heightmarch::bench {

struct BenchConfig {
  int view_size = 1024;
  int resolution = 512;
  std::vector<std::string> heightfields = {"bricks", "terrain"};
  std::vector<int> threads;  // empty: 1 and all cores
  std::vector<Isa> isas;     // empty: every ISA the CPU runs
};

// BM_Trace, BM_SamplerRoofline and BM_NaivePort for every configuration.
void register_benchmarks(const BenchConfig& config);

}  // namespace heightmarch::bench
