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
bool cpu_supports(Isa isa);
Isa best_isa();                           // the widest the CPU runs
std::vector<Isa> supported_isas();        // narrowest first
std::string isa_names();                  // "scalar, sse4.2, avx2, avx512", for help texts

// The one name -> ISA: the ISA to_string() names so, whichever CPU runs it (a recorded run's
// backend); throws InputError for an unknown name.
Isa isa_named(const std::string& name);

// "auto" (or empty) = best_isa(); otherwise isa_named(name), which the CPU must run.
// Throws InputError for unknown names and ISAs the CPU lacks.
Isa parse_isa(const std::string& name);

// --isa if given, else $HEIGHTMARCH_ISA, else auto.
Isa select_isa(const std::string& option);

}  // namespace heightmarch
