#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/rays.hpp"
#include "util/input_file.hpp"

namespace heightmarch {
namespace {

constexpr std::size_t kMaxCsvRays = 64u << 20;  // 67 M rays, about 2.4 GB of batch and hits

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace

RayBatch load_rays_csv(const std::string& path, int tile_size) {
  // A regular file no larger than the budget: /dev/zero or a FIFO would read forever.
  const std::string text = read_input_file(path, "rays file", memory_budget());
  // The rays' memory, padding included, before any column is allocated: every line a ray.
  const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
  check_memory_budget(double(text.size()) +
                          (kBytesPerRayCsvRow + kBytesPerRay * padding_factor(tile_size)) * double(lines),
                      path + " (up to " + std::to_string(lines) + " rays)");
  // One line per call, read in place (a copy of a 100 MB file is 100 MB more).
  std::size_t at = 0;
  const auto next_line = [&](std::string& line) {
    if (at >= text.size()) return false;
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    line.assign(text, at, end - at);
    at = end + 1;
    return true;
  };
  std::string line;
  if (!next_line(line)) throw InputError(path + ": empty rays file (expected header tx,ty,vx,vy,vz)");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark (spreadsheet exports)
  const std::vector<std::string> expected = {"tx", "ty", "vx", "vy", "vz"};
  if (split_fields(line) != expected)
    throw InputError(path + ":1: header must be tx,ty,vx,vy,vz (found '" + line.substr(0, 40) + "')");
  std::vector<float> columns[5];
  std::size_t line_number = 1;
  while (next_line(line)) {
    ++line_number;
    if (trim(line).empty()) continue;
    const std::vector<std::string> fields = split_fields(line);
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (fields.size() != 5)
      throw InputError(where + "expected 5 columns, found " + std::to_string(fields.size()));
    for (int c = 0; c < 5; ++c) {
      // Read as a double, then rounded: 1e-50 is a number (0 as a float), 1e50 is out of range.
      double value = 0.0;
      const char* end = fields[c].data() + fields[c].size();
      const auto [ptr, ec] = std::from_chars(fields[c].data(), end, value);
      if (fields[c].empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
        throw InputError(where + expected[c] + " '" + fields[c] + "' is not a number");
      if (ec == std::errc::result_out_of_range && std::fabs(value) > 1.0)
        throw InputError(where + expected[c] + " '" + fields[c] + "' is beyond a float's range");
      if (std::isfinite(value) && std::fabs(value) > double(std::numeric_limits<float>::max()))
        throw InputError(where + expected[c] + " '" + fields[c] + "' is beyond a float's range");
      columns[c].push_back(float(value));
    }
    if (columns[0].size() > kMaxCsvRays)
      throw InputError(path + ": more than " + std::to_string(kMaxCsvRays) + " rays");
  }
  if (columns[0].empty()) throw InputError(path + ": no rays after the header");
  try {
    return make_ray_list(columns[0], columns[1], columns[2], columns[3], columns[4], tile_size);
  } catch (const InputError& e) {
    // make_ray_list counts rays from 1: ray N is the file's line N + 1.
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace heightmarch
