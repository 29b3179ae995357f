#include "heightmarch/isa.hpp"

#include <algorithm>
#include <cstdlib>
#include <optional>
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

// The ISA named `name` (as to_string names it), whatever the CPU; none for an unknown name.
std::optional<Isa> find_isa(std::string_view name) {
  for (Isa isa : all_isas())
    if (name == to_string(isa)) return isa;
  return std::nullopt;
}

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

// Whether the hardware runs the ISA: every feature of its row's space-separated list.
bool hardware_runs(Isa isa) {
  std::string_view features = "?";  // no ISA of the list: none of its features is known
#define HEIGHTMARCH_ISA_FEATURES(id, name, width, march_width, walk_width, cpu_features) \
  if (isa == Isa::id) features = cpu_features;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_FEATURES)
#undef HEIGHTMARCH_ISA_FEATURES
  if (features == "?") return false;
  while (!features.empty()) {
    const std::size_t end = std::min(features.find(' '), features.size());
    if (!cpu_has(features.substr(0, end))) return false;
    features.remove_prefix(std::min(end + 1, features.size()));
  }
  return true;
}

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

// $HEIGHTMARCH_MAX_ISA, none when unset or empty. Read on every call, as $HEIGHTMARCH_ISA is, so
// that a test can set it.
std::optional<Isa> isa_cap() {
  const std::string name = environment("HEIGHTMARCH_MAX_ISA");
  if (name.empty()) return std::nullopt;
  if (auto isa = find_isa(name)) return isa;
  throw InputError("HEIGHTMARCH_MAX_ISA=" + name + ": not an ISA (" + isa_names() + ")");
}

}  // namespace

bool cpu_supports(Isa isa) {
  const std::optional<Isa> cap = isa_cap();
  return hardware_runs(isa) && (!cap || int(isa) <= int(*cap));
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
  if (const std::optional<Isa> isa = find_isa(name)) return *isa;
  throw InputError("unknown ISA '" + name + "' (" + isa_names() + ")");
}

void check_cpu_supports(Isa isa, const std::string& where) {
  if (!cpu_supports(isa))
    throw InputError(where + ": this CPU does not run " + to_string(isa) + "; it runs " +
                     runnable_isa_names());
}

std::string runnable_isa_names() {
  std::string names;
  bool capped = false;
  for (Isa isa : all_isas()) {
    if (cpu_supports(isa)) names += (names.empty() ? "" : ", ") + to_string(isa);
    capped = capped || (hardware_runs(isa) && !cpu_supports(isa));
  }
  const std::optional<Isa> cap = isa_cap();
  return capped ? names + " (capped by HEIGHTMARCH_MAX_ISA=" + to_string(*cap) + ")" : names;
}

Isa parse_isa(const std::string& name, const std::string& where) {
  if (name.empty() || name == "auto") return best_isa();
  const std::optional<Isa> isa = find_isa(name);
  // "--isa avx512", "HEIGHTMARCH_ISA=avx512": the value as it was given
  const std::string given = where + (where.rfind("--", 0) == 0 ? " " : "=") + name;
  if (!isa) throw InputError(given + ": unknown ISA (" + isa_names() + " or auto)");
  check_cpu_supports(*isa, given);
  return *isa;
}

Isa select_isa(const std::string& option) {
  if (!option.empty()) return parse_isa(option, "--isa");
  return parse_isa(environment("HEIGHTMARCH_ISA"), "HEIGHTMARCH_ISA");
}

}  // namespace heightmarch
