// libFuzzer: the environment's and the size parsers (HEIGHTMARCH_MEMORY_LIMIT, HEIGHTMARCH_ISA,
// --view) give a value in range or an InputError: never a crash, undefined behaviour (UBSan)
// or a value out of range. 1e30, inf and 2e19 once overflowed a double-to-size_t conversion.
#include <cstdint>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/isa.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/views.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  using namespace heightmarch;
  try {
    const std::size_t bytes = parse_memory_limit(text);
    if (bytes < 1 || bytes > (std::size_t(1) << 62)) __builtin_trap();
  } catch (const InputError&) {
  }
  try {
    parse_isa(text);
  } catch (const InputError&) {
  }
  try {
    const ViewSpec view = parse_view(text, 64, 48);
    if (view.kind == ViewSpec::Kind::sweep && !(view.theta_degrees >= 0.0f && view.theta_degrees <= 89.0f))
      __builtin_trap();
  } catch (const InputError&) {
  }
  return 0;
}
