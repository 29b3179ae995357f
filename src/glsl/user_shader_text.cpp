#include "glsl/user_shader_text.hpp"

#include <algorithm>
#include <cctype>

#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

bool is_word(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// A #version line, or the file's own declaration of one of the harness's uniforms
// ("uniform TYPE NAME;"). Scanned by hand: std::regex recurses per character and overflows the
// stack on a line of some 30,000 characters.
bool harness_declaration(const std::string& line) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  std::size_t i = 0;
  const auto skip_spaces = [&] {
    const std::size_t start = i;
    while (i < line.size() && is_space(line[i])) ++i;
    return i > start;
  };
  const auto word = [&] {
    const std::size_t start = i;
    while (i < line.size() && is_word(line[i])) ++i;
    return line.substr(start, i - start);
  };
  skip_spaces();
  if (line.compare(i, 8, "#version") == 0) return i + 8 == line.size() || !is_word(line[i + 8]);
  if (word() != "uniform" || !skip_spaces() || word().empty() || !skip_spaces()) return false;
  const std::string name = word();
  skip_spaces();
  static const char* const names[] = {"depthMap",  "heightScale", "height_scale",
                                      "numLayers", "minLayers",   "maxLayers"};
  return i < line.size() && line[i] == ';' &&
         std::find(std::begin(names), std::end(names), name) != std::end(names);
}

// Reads the digits at `at` (at most 15, so no overflow) into `value`; false if there are none.
bool read_number(const std::string& text, std::size_t& at, long long& value) {
  const std::size_t start = at;
  value = 0;
  while (at < text.size() && at - start < 15 && std::isdigit(static_cast<unsigned char>(text[at])))
    value = value * 10 + (text[at++] - '0');
  return at > start && (at == text.size() || !std::isdigit(static_cast<unsigned char>(text[at])));
}

// One log line with each "S:L(C)" location rewritten; scanned by hand, as above.
std::string map_locations(const std::string& line, const std::string& path) {
  std::string out;
  std::size_t i = 0;
  // Each pass consumes at least one character.
  while (i < line.size()) {
    const bool starts =
        std::isdigit(static_cast<unsigned char>(line[i])) && (i == 0 || !is_word(line[i - 1]));
    std::size_t at = i;
    long long source = 0, row = 0, column = 0;
    if (starts && read_number(line, at, source) && at < line.size() && line[at] == ':' &&
        read_number(line, ++at, row) && at < line.size() && line[at] == '(' &&
        read_number(line, ++at, column) && at < line.size() && line[at] == ')') {
      const bool harness = row >= kHarnessFirstLine;
      out += (harness ? std::string("harness") : path) + ":" +
             std::to_string(harness ? row - kHarnessFirstLine + 1 : row) + ":" + std::to_string(column);
      i = at + 1;
    } else {
      out += line[i++];
    }
  }
  return out;
}

// The line (from 1) of a definition of main() ("void main(", outside // comments), or 0: a whole
// fragment shader rather than the function the harness calls. Scanned by hand, as above.
std::size_t main_definition_line(const std::string& text) {
  std::size_t line = 1, start = 0;
  // One line per pass, as in user_source.
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string code = text.substr(start, end - start);
    code = code.substr(0, code.find("//"));
    for (std::size_t at = code.find("main"); at != std::string::npos; at = code.find("main", at + 1)) {
      std::size_t after = at + 4, before = at;
      while (after < code.size() && (code[after] == ' ' || code[after] == '\t')) ++after;
      while (before > 0 && (code[before - 1] == ' ' || code[before - 1] == '\t')) --before;
      const bool word =
          (at == 0 || !is_word(code[at - 1])) && (at + 4 == code.size() || !is_word(code[at + 4]));
      if (word && after < code.size() && code[after] == '(' && before >= 4 &&
          code.compare(before - 4, 4, "void") == 0 && (before == 4 || !is_word(code[before - 5])))
        return line;
    }
    start = end + 1;
    ++line;
  }
  return 0;
}

}  // namespace

std::string user_source(const std::string& text, const std::string& path) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw InputError(path + ": empty shader file");
  // The source reaches GL as a C string: the compiler would stop at a NUL byte and run the rest unread.
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos)
    throw InputError(path + ": holds a NUL byte (line " +
                     std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) +
                     "): not a GLSL text file");
  if (const std::size_t line = main_definition_line(text))
    throw InputError(
        path + ":" + std::to_string(line) +
        ": defines main(): a function vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) is expected, not a "
        "whole shader (give the function, and what it calls, in a file of its own)");
  if (text.find("ParallaxMapping") == std::string::npos)
    throw InputError(path + ": does not define vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir)");
  std::string out;
  out.reserve(text.size() + 1);
  std::size_t start = 0;
  // One line per pass; each pass moves start past a newline or to the end.
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    out += (harness_declaration(line) ? "" : line) + "\n";
    start = end + 1;
  }
  return out;
}

std::string user_log(const std::string& log, const std::string& path) {
  std::string joined;
  std::size_t start = 0;
  // One line per pass, as in user_source.
  while (start < log.size()) {
    std::size_t end = log.find('\n', start);
    if (end == std::string::npos) end = log.size();
    const std::string line = log.substr(start, end - start);
    if (!line.empty()) joined += (joined.empty() ? "" : "; ") + map_locations(line, path);
    start = end + 1;
    if (joined.size() > kMaxQuotedLogBytes) break;
  }
  if (joined.size() <= kMaxQuotedLogBytes) return joined;
  return joined.substr(0, kMaxQuotedLogBytes) + " ... (the log goes on for " + std::to_string(log.size()) +
         " bytes)";
}

}  // namespace heightmarch
