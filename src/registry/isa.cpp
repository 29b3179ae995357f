#include "heightmarch/isa.hpp"

#include <cstdlib>

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

bool cpu_supports(Isa isa) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();  // the x86 list's checks call __builtin_cpu_supports
#endif
#define HEIGHTMARCH_ISA_CHECK(id, name, width, march_width, walk_width, check) \
  if (isa == Isa::id) return check;
  HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_CHECK)
#undef HEIGHTMARCH_ISA_CHECK
  return false;
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

Isa parse_isa(const std::string& name) {
  if (name.empty() || name == "auto") return best_isa();
  for (Isa isa : all_isas()) {
    if (name != to_string(isa)) continue;
    if (!cpu_supports(isa)) throw InputError("ISA " + name + " is not supported by this CPU");
    return isa;
  }
  throw InputError("unknown ISA '" + name + "' (" + isa_names() + " or auto)");
}

Isa select_isa(const std::string& option) {
  if (!option.empty()) return parse_isa(option);
  const char* env = std::getenv("HEIGHTMARCH_ISA");
  return parse_isa(env ? env : "");
}

}  // namespace heightmarch
