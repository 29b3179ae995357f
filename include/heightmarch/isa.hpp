#pragma once
// Instruction sets the packet kernels are compiled for: one list, detected once at start-up.
//
// Adding an ISA: its packet header (include/heightmarch/simd/), its kernel translation unit
// (src/isa/kernels_<id>.cpp), one row here, and its compiler flags in CMakeLists.txt.
#include <array>
#include <string>
#include <string_view>
#include <vector>

// X(id, name, CPU check): narrowest first; each CPU check is an expression over
// __builtin_cpu_supports that says whether this CPU runs the ISA's kernels.
#define HEIGHTMARCH_ISAS(X)                                                                     \
  X(scalar, "scalar", true)                                                                    \
  X(sse42, "sse4.2", __builtin_cpu_supports("sse4.2"))                                         \
  X(avx2, "avx2",                                                                              \
    __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&                         \
        __builtin_cpu_supports("bmi2"))                                                        \
  X(avx512, "avx512",                                                                          \
    __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&                         \
        __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("avx512f") &&                 \
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&            \
        __builtin_cpu_supports("avx512vl"))

namespace heightmarch {

#define HEIGHTMARCH_ISA_ENUM(id, ...) id,
enum class Isa { HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_ENUM) };
#undef HEIGHTMARCH_ISA_ENUM

#define HEIGHTMARCH_ISA_COUNT(...) +1
inline constexpr int kIsaCount = 0 HEIGHTMARCH_ISAS(HEIGHTMARCH_ISA_COUNT);
#undef HEIGHTMARCH_ISA_COUNT

const std::array<Isa, kIsaCount>& all_isas();  // narrowest first
std::string to_string(Isa isa);                // scalar, sse4.2, avx2, avx512
bool cpu_supports(Isa isa);
Isa best_isa();                           // the widest the CPU runs
std::vector<Isa> supported_isas();        // narrowest first
std::string isa_names();                  // "scalar, sse4.2, avx2, avx512", for help texts

// "auto" (or empty) = best_isa(); otherwise the named ISA, which the CPU must run.
// Throws InputError for unknown names and ISAs the CPU lacks.
Isa parse_isa(const std::string& name);

// --isa if given, else $HEIGHTMARCH_ISA, else auto.
Isa select_isa(const std::string& option);

}  // namespace heightmarch
