#pragma once
// printf into a std::string of any length (a claim's rule runs to several hundred characters).
#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>

namespace heightmarch {

std::string string_format(const char* format, ...) __attribute__((format(printf, 1, 2)));
inline std::string string_format(const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int length = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string text(std::size_t(std::max(length, 0)), '\0');
  std::vsnprintf(text.data(), text.size() + 1, format, again);
  va_end(again);
  return text;
}

}  // namespace heightmarch
