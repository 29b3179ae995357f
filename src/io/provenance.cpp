#include "io/provenance.hpp"

#include <ctime>
#include <fstream>
#include <thread>

#include "build_info.hpp"

namespace heightmarch {

Provenance provenance() {
  Provenance p;
  p.commit = kBuildCommit;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const auto colon = line.find(':');
    if (colon != std::string::npos) p.cpu = line.substr(line.find_first_not_of(' ', colon + 1));
    break;
  }
  if (p.cpu.empty()) p.cpu = "unknown CPU";
  p.cores = int(std::thread::hardware_concurrency());
  p.compiler = kBuildCompiler;
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  p.date = buf;
  p.build_type = HEIGHTMARCH_BUILD_TYPE;
  return p;
}

}  // namespace heightmarch
