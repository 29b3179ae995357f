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

// The most characters of an error line (its program's name aside): a line that echoes a user's
// string (a 10 KB device name, a 4 KB path) stays a line a person reads.
inline constexpr std::size_t kMaxErrorLine = 1000;

// printable(text), cut in its middle to at most about kMaxErrorLine characters when longer: its
// head and tail (where an error line says what is wrong) around "...[N characters cut]...", never
// splitting a character or an escape. Applying it twice changes nothing.
std::string error_line(std::string_view text);

// Its message goes through error_line(): an error quoting input is one safe line of bounded length
// wherever it is printed.
struct InputError : std::runtime_error {
  explicit InputError(const std::string& what) : std::runtime_error(error_line(what)) {}
};

}  // namespace heightmarch
