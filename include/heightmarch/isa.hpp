#pragma once
// Instruction sets the packet kernels are compiled for: one list per architecture
// (cmake/isa_list.cmake, generated into heightmarch/isa_list.hpp), detected once at start-up.
//
// Adding an ISA: one row in cmake/isa_list.cmake, and its packet header in src/simd/ if no
// existing one fits its width and instructions.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "heightmarch/isa_list.hpp"

namespace heightmarch {

#define HEIGHTMARCH_ISA_ENUM(id, ...) id,
enum class Isa { HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_ENUM) };
#undef HEIGHTMARCH_ISA_ENUM

#define HEIGHTMARCH_ISA_COUNT(...) +1
inline constexpr int kIsaCount = 0 HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_COUNT);
#undef HEIGHTMARCH_ISA_COUNT

const std::array<Isa, kIsaCount>& all_isas();  // narrowest first
std::string to_string(Isa isa);                // its name: scalar, sse4.2, avx2, avx512
std::string_view isa_id(Isa isa);              // an identifier: scalar, sse42, avx2, avx512
// The CPU runs it and $HEIGHTMARCH_MAX_ISA, where set, allows it: a cap on the widest ISA (avx2,
// sse4.2 or scalar) under which a CPU is taken for an older one by everything (the suite's ISAs,
// the dispatch, the tests), so that one machine proves the project on older cores. Throws
// InputError for a cap that names no ISA.
bool cpu_supports(Isa isa);
Isa best_isa();                     // the widest the CPU runs
std::vector<Isa> supported_isas();  // narrowest first
std::string isa_names();            // "scalar, sse4.2, avx2, avx512", for help texts
std::string runnable_isa_names();   // the ISAs the CPU runs, and the cap where it hides one

// The one name -> ISA: the ISA to_string() names so, whichever CPU runs it (a recorded run's
// backend); throws InputError for an unknown name.
Isa isa_named(const std::string& name);

// Throws InputError "<where>: this CPU does not run avx512; it runs scalar, sse4.2, avx2" unless
// cpu_supports(isa).
void check_cpu_supports(Isa isa, const std::string& where);

// "auto" (or empty) = best_isa(); otherwise the named ISA, which the CPU must run. Throws
// InputError for unknown names and ISAs the CPU lacks, naming `where` (an option or a variable)
// and the ISAs this CPU runs.
Isa parse_isa(const std::string& name, const std::string& where = "--isa");

// --isa if given, else $HEIGHTMARCH_ISA, else auto.
Isa select_isa(const std::string& option);

}  // namespace heightmarch
