#pragma once
// Errors caused by the user's input (files, options). The CLI prints them as one line and exits 2.
#include <stdexcept>
#include <string>
#include <string_view>

namespace heightmarch {

// Text fit to quote in an error line, whatever bytes it came with (a file name, an option's value,
// a field of a file, a compiler's log): bytes a terminal acts on or cannot show (C0 and C1
// controls, DEL, newlines, bidirectional overrides, bytes of no valid UTF-8 character) become
// \xNN; printable UTF-8 stays as it is. Applying it twice changes nothing.
std::string printable(std::string_view text);

// Its message goes through printable(): an error quoting input is one safe line wherever it is printed.
struct InputError : std::runtime_error {
  explicit InputError(const std::string& what) : std::runtime_error(printable(what)) {}
};

}  // namespace heightmarch
