// libFuzzer: a brought-in shader's text through the harness's line filter (user_source) and any
// text as a compiler log through the location mapping (user_log): a value or an InputError,
// never a crash, and the filter keeps the file's line count. Run with a -max_len of a long line
// (scripts/fuzz): std::regex once overflowed the stack on a line of 30,000 characters.
#include <algorithm>
#include <cstdint>
#include <string>

#include "glsl/user_shader_text.hpp"
#include "heightmarch/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const std::string source = heightmarch::user_source(text, "f.glsl");
    const auto lines = [](const std::string& s) { return std::count(s.begin(), s.end(), '\n'); };
    if (lines(source) != lines(text) + (text.empty() || text.back() != '\n')) __builtin_trap();
  } catch (const heightmarch::InputError&) {
  }
  const std::string log = heightmarch::user_log(text, "f.glsl");
  if (log.find('\n') != std::string::npos) __builtin_trap();
  return 0;
}
