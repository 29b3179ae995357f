#pragma once
// Markdown written by the tools (claims.md, the recommendation's table): every string that enters
// it, a cell, a heading or a line of prose from a name or a figure, goes through markdown_text,
// so a map named with markup stays text: no link, image or HTML, no cut table row, no split
// heading. heightmarch_tools.escape.markdown() is the same rule for the report.
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch {

// The text printable (control characters as \xNN), line breaks and tabs as spaces, and the
// characters that make Markdown markup escaped with a backslash.
inline std::string markdown_text(const std::string& text) {
  std::string flat = text;
  for (char& c : flat)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  std::string out;
  for (char c : printable(flat)) {
    if (std::string_view("\\`*_[]<>#|~&$").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

}  // namespace heightmarch
