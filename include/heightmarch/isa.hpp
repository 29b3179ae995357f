#pragma once
// Instruction sets the packet kernels are compiled for, detected once at start-up.
#include <string>
#include <vector>

namespace heightmarch {

enum class Isa { scalar, sse42, avx2, avx512 };

std::string to_string(Isa isa);           // scalar, sse4.2, avx2, avx512
bool cpu_supports(Isa isa);
Isa best_isa();                           // the widest the CPU runs
std::vector<Isa> supported_isas();        // narrowest first

// "auto" (or empty) = best_isa(); otherwise the named ISA, which the CPU must run.
// Throws InputError for unknown names and ISAs the CPU lacks.
Isa parse_isa(const std::string& name);

// --isa if given, else $HEIGHTMARCH_ISA, else auto.
Isa select_isa(const std::string& option);

}  // namespace heightmarch
