#include "heightmarch/isa.hpp"

#include <cstdlib>

#include "heightmarch/error.hpp"

namespace heightmarch {

std::string to_string(Isa isa) {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse42: return "sse4.2";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "?";
}

bool cpu_supports(Isa isa) {
  __builtin_cpu_init();
  switch (isa) {
    case Isa::scalar: return true;
    case Isa::sse42: return __builtin_cpu_supports("sse4.2");
    case Isa::avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
             __builtin_cpu_supports("bmi2");
    case Isa::avx512:
      return cpu_supports(Isa::avx2) && __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl");
  }
  return false;
}

std::vector<Isa> supported_isas() {
  std::vector<Isa> isas;
  for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512})
    if (cpu_supports(isa)) isas.push_back(isa);
  return isas;
}

Isa best_isa() { return supported_isas().back(); }

Isa parse_isa(const std::string& name) {
  if (name.empty() || name == "auto") return best_isa();
  for (Isa isa : {Isa::scalar, Isa::sse42, Isa::avx2, Isa::avx512}) {
    if (name != to_string(isa)) continue;
    if (!cpu_supports(isa)) throw InputError("ISA " + name + " is not supported by this CPU");
    return isa;
  }
  throw InputError("unknown ISA '" + name + "' (scalar, sse4.2, avx2, avx512 or auto)");
}

Isa select_isa(const std::string& option) {
  if (!option.empty()) return parse_isa(option);
  const char* env = std::getenv("HEIGHTMARCH_ISA");
  return parse_isa(env ? env : "");
}

}  // namespace heightmarch
