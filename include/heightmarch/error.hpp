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

// One character of text at byte `at`, as printable() reads it: its length in bytes (1 for a byte
// of no valid UTF-8 character), its code point (-1 for such a byte), and whether printable() keeps
// it as it is. A writer of another format (JSON) escapes the others in its own way.
struct TextCharacter {
  std::size_t length;
  long code;
  bool printable;
};
TextCharacter character_at(std::string_view text, std::size_t at);

// Its message goes through printable(): an error quoting input is one safe line wherever it is printed.
struct InputError : std::runtime_error {
  explicit InputError(const std::string& what) : std::runtime_error(printable(what)) {}
};

}  // namespace heightmarch
