#include "heightmarch/isa.hpp"

#include <cstdlib>
#include <optional>

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

bool hardware_runs(Isa isa) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();  // the x86 list's checks call __builtin_cpu_supports
#endif
#define HEIGHTMARCH_ISA_CHECK(id, name, width, march_width, walk_width, check) \
  if (isa == Isa::id) return check;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_CHECK)
#undef HEIGHTMARCH_ISA_CHECK
  return false;
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

void check_cpu_supports(Isa isa, const std::string& where) {
  if (!cpu_supports(isa))
    throw InputError(where + ": this CPU does not run " + to_string(isa) + "; it runs " + runnable_isa_names());
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
