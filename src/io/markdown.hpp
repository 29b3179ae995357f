#pragma once
// Markdown written by the tools (claims.md): every table cell goes through markdown_cell, so a
// '|' in a figure or a rule ("|grad D|") cannot cut the table. heightmarch_tools.escape.markdown()
// does the same for the report.
#include <string>

namespace heightmarch {

// The text as one table cell: '|' escaped, line breaks as spaces.
inline std::string markdown_cell(const std::string& text) {
  std::string cell;
  for (char c : text) {
    if (c == '|')
      cell += "\\|";
    else if (c == '\n' || c == '\r')
      cell += ' ';
    else
      cell += c;
  }
  return cell;
}

}  // namespace heightmarch
