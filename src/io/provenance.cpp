#include "io/provenance.hpp"

#include <ctime>
#include <fstream>
#include <thread>

#include "build_info.hpp"

namespace heightmarch {

Provenance provenance() {
  Provenance p;
  p.commit = kBuildCommit;
  // The first processor's model name, with its family and model: virtual machines often show a
  // bare "AMD EPYC", which the two numbers tell apart (family 25 model 17 is Zen 4).
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string family, model;
  auto value = [](const std::string& line) {
    const auto colon = line.find(':');
    const auto start =
        colon == std::string::npos ? std::string::npos : line.find_first_not_of(' ', colon + 1);
    return start == std::string::npos ? std::string() : line.substr(start);
  };
  for (std::string line; std::getline(cpuinfo, line) && !line.empty();) {
    if (line.rfind("model name", 0) == 0)
      p.cpu = value(line);
    else if (line.rfind("cpu family", 0) == 0)
      family = value(line);
    else if (line.rfind("model\t", 0) == 0 || line.rfind("model :", 0) == 0)
      model = value(line);
  }
  if (p.cpu.empty()) p.cpu = "unknown CPU";
  if (!family.empty() && !model.empty()) p.cpu += " (family " + family + ", model " + model + ")";
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
