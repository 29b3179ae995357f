#pragma once
// Where a result came from: commit, machine, compiler, date.
#include <string>

namespace heightmarch {

struct Provenance {
  std::string commit;  // short hash, "+dirty" when built from a modified tree
  std::string cpu;     // model name from /proc/cpuinfo
  int cores = 0;
  std::string compiler;
  std::string date;        // UTC, ISO 8601
  std::string build_type;  // CMAKE_BUILD_TYPE of the binaries
};

Provenance provenance();

}  // namespace heightmarch
