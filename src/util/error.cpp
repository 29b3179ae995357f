#include "heightmarch/error.hpp"

#include <cstdint>
#include <cstdio>
#include <vector>

namespace heightmarch {
namespace {

// The length of the valid UTF-8 character at text[at] and its code point; 0 when the bytes there
// are no character (a stray continuation byte, an overlong form, a surrogate, a truncated sequence).
std::size_t utf8_character(std::string_view text, std::size_t at, std::uint32_t& code) {
  const auto byte = [&](std::size_t i) { return std::uint32_t(static_cast<unsigned char>(text[i])); };
  const std::uint32_t lead = byte(at);
  std::size_t length = 0;
  std::uint32_t smallest = 0;
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2, code = lead & 0x1f, smallest = 0x80;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3, code = lead & 0x0f, smallest = 0x800;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4, code = lead & 0x07, smallest = 0x10000;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(at + i) & 0xc0) != 0x80) return 0;
    code = (code << 6) | (byte(at + i) & 0x3f);
  }
  if (code < smallest || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return 0;
  return length;
}

// C1 controls (an 8-bit CSI is 0x9b) and the bidirectional embeddings, overrides and isolates,
// which reorder what follows them on the line.
bool acts_on_terminal(std::uint32_t code) {
  return (code >= 0x80 && code <= 0x9f) || (code >= 0x202a && code <= 0x202e) ||
         (code >= 0x2066 && code <= 0x2069);
}

}  // namespace

TextCharacter character_at(std::string_view text, std::size_t at) {
  const unsigned char c = static_cast<unsigned char>(text[at]);
  if (c < 0x80) return {1, long(c), c >= 0x20 && c != 0x7f};
  std::uint32_t code = 0;
  const std::size_t length = utf8_character(text, at, code);
  if (length == 0) return {1, -1, false};
  return {length, long(code), !acts_on_terminal(code)};
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t at = 0; at < text.size();) {
    const TextCharacter c = character_at(text, at);
    if (c.printable) {
      out.append(text.substr(at, c.length));
    } else {
      for (std::size_t i = 0; i < c.length; ++i) {
        char hex[5];
        std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(text[at + i]));
        out += hex;
      }
    }
    at += c.length;
  }
  return out;
}

std::string error_line(std::string_view text) {
  // printable(text), and where each character's piece of it ends (itself, or its escapes).
  std::string shown;
  std::vector<std::size_t> ends;
  for (std::size_t at = 0; at < text.size();) {
    const TextCharacter c = character_at(text, at);
    shown += printable(text.substr(at, c.length));
    ends.push_back(shown.size());
    at += c.length;
  }
  if (shown.size() <= kMaxErrorLine) return shown;
  const auto start = [&](std::size_t piece) { return piece ? ends[piece - 1] : 0; };
  // Three fifths of the line for the head, a third for the tail, whole pieces each.
  std::size_t head = 0, tail = ends.size();
  while (head < ends.size() && ends[head] <= kMaxErrorLine * 3 / 5) ++head;
  while (tail > head && shown.size() - start(tail - 1) <= kMaxErrorLine / 3) --tail;
  return shown.substr(0, start(head)) + "...[" + std::to_string(tail - head) + " characters cut]..." +
         shown.substr(start(tail));
}

}  // namespace heightmarch
