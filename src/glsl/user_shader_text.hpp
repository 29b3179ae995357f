#pragma once
// A brought-in shader's text as the harness compiles it, and the compiler's log read back in the
// file's own line numbers. No GL here, so the fuzz targets reach it (tests/fuzz/fuzz_shader_text.cpp).
#include <cstddef>
#include <string>

namespace heightmarch {

// The largest brought-in shader file read (a tutorial's is a few KB).
inline constexpr std::size_t kMaxShaderBytes = std::size_t(1) << 20;

// The harness's code is numbered from this line on (#line), far beyond any line of a file of at
// most kMaxShaderBytes: Mesa reports some errors with source string 0 whatever their origin, so
// the line number alone tells the file's lines from the harness's.
inline constexpr long long kHarnessFirstLine = 10'000'000;

// The file's text with its #version line and its declarations of the harness's uniforms blanked
// (kept as empty lines, so line numbers hold). Throws InputError naming `path` for a text that is
// empty, a whole shader (it defines main()) or defines no ParallaxMapping.
std::string user_source(const std::string& text, const std::string& path);

// The compiler's log, lines joined with "; ", each "S:L(C)" location rewritten as "PATH:L:C" (a
// line of the file) or "harness:L:C" (a line of heightmarch's own code); an error line quotes its
// first kMaxQuotedLogBytes (the first errors are the ones that tell).
inline constexpr std::size_t kMaxQuotedLogBytes = 2048;
std::string user_log(const std::string& log, const std::string& path);

}  // namespace heightmarch
