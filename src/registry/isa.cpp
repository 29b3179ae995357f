#include "heightmarch/isa.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch {

const std::array<Isa, kIsaCount>& all_isas() {
#define HEIGHTMARCH_ISA_ID(id, ...) Isa::id,
  static const std::array<Isa, kIsaCount> isas = {HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_ID)};
#undef HEIGHTMARCH_ISA_ID
  return isas;
}

std::string to_string(Isa isa) {
#define HEIGHTMARCH_ISA_NAME(id, name, ...) \
  if (isa == Isa::id) return name;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_NAME)
#undef HEIGHTMARCH_ISA_NAME
  return "?";
}

std::string_view isa_id(Isa isa) {
#define HEIGHTMARCH_ISA_ID_NAME(id, ...) \
  if (isa == Isa::id) return #id;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_ID_NAME)
#undef HEIGHTMARCH_ISA_ID_NAME
  return "?";
}

namespace {

// Whether the running CPU has a feature the ISA list names (as __builtin_cpu_supports does, which
// takes only a literal: one line per feature a row of the list needs).
bool cpu_has(std::string_view feature) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
#define HEIGHTMARCH_CPU_FEATURE(name) \
  if (feature == name) return __builtin_cpu_supports(name);
  HEIGHTMARCH_CPU_FEATURE("sse4.2")
  HEIGHTMARCH_CPU_FEATURE("avx2")
  HEIGHTMARCH_CPU_FEATURE("fma")
  HEIGHTMARCH_CPU_FEATURE("bmi2")
  HEIGHTMARCH_CPU_FEATURE("avx512f")
  HEIGHTMARCH_CPU_FEATURE("avx512bw")
  HEIGHTMARCH_CPU_FEATURE("avx512dq")
  HEIGHTMARCH_CPU_FEATURE("avx512vl")
#undef HEIGHTMARCH_CPU_FEATURE
#endif
  throw std::logic_error("the ISA list names the CPU feature '" + std::string(feature) +
                         "', which src/registry/isa.cpp does not check");
}

}  // namespace

bool cpu_supports(Isa isa) {
  std::string_view features = "?";  // no ISA of the list: none of its features is known
#define HEIGHTMARCH_ISA_FEATURES(id, name, width, march_width, walk_width, cpu_features) \
  if (isa == Isa::id) features = cpu_features;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_FEATURES)
#undef HEIGHTMARCH_ISA_FEATURES
  if (features == "?") return false;
  // Every feature of the row's space-separated list.
  while (!features.empty()) {
    const std::size_t end = std::min(features.find(' '), features.size());
    if (!cpu_has(features.substr(0, end))) return false;
    features.remove_prefix(std::min(end + 1, features.size()));
  }
  return true;
}

std::vector<Isa> supported_isas() {
  std::vector<Isa> isas;
  for (Isa isa : all_isas())
    if (cpu_supports(isa)) isas.push_back(isa);
  return isas;
}

Isa best_isa() { return supported_isas().back(); }

std::string isa_names() {
  std::string names;
  for (Isa isa : all_isas()) names += (names.empty() ? "" : ", ") + to_string(isa);
  return names;
}

Isa isa_named(const std::string& name) {
  for (Isa isa : all_isas())
    if (name == to_string(isa)) return isa;
  throw InputError("unknown ISA '" + name + "' (" + isa_names() + ")");
}

Isa parse_isa(const std::string& name) {
  if (name.empty() || name == "auto") return best_isa();
  const Isa isa = isa_named(name);
  if (!cpu_supports(isa)) throw InputError("ISA " + name + " is not supported by this CPU");
  return isa;
}

Isa select_isa(const std::string& option) {
  if (!option.empty()) return parse_isa(option);
  const char* env = std::getenv("HEIGHTMARCH_ISA");
  return parse_isa(env ? env : "");
}

}  // namespace heightmarch
