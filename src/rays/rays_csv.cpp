#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "heightmarch/rays.hpp"
#include "rays/camera_poses.hpp"
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

// The file's lines one at a time, read through a buffer of kChunkBytes (a 3 GB file is never
// held whole); a line longer than kMaxLineBytes is an error, not a growing buffer, wherever it lies
// in the buffer (every line is measured, not only one that crosses a chunk).
class LineReader {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t(1) << 20;
  static constexpr std::size_t kMaxLineBytes = 4096;

  LineReader(InputFile& file, const std::string& path) : file_(file), path_(path) {}

  bool next(std::string& line) {
    // Each pass takes one line from the buffer, or reads more (at least a byte), or ends.
    for (;;) {
      const std::size_t newline = buffer_.find('\n', at_);
      if (newline != std::string::npos) {
        if (newline - at_ > kMaxLineBytes) too_long();
        line.assign(buffer_, at_, newline - at_);
        consumed_ += newline + 1 - at_;
        at_ = newline + 1;
        ++number_;
        return true;
      }
      if (buffer_.size() - at_ > kMaxLineBytes) too_long();
      buffer_.erase(0, at_);
      at_ = 0;
      const std::size_t kept = buffer_.size();
      buffer_.resize(kept + kChunkBytes);
      const std::size_t n = file_.read(buffer_.data() + kept, kChunkBytes);
      buffer_.resize(kept + n);
      if (n > 0) continue;
      if (buffer_.empty()) return false;
      line = std::move(buffer_);  // the last line, without a newline
      consumed_ += line.size();
      buffer_.clear();
      ++number_;
      return true;
    }
  }
  std::size_t number() const { return number_; }         // of the last line returned, from 1
  std::uintmax_t consumed() const { return consumed_; }  // bytes of the lines returned

 private:
  [[noreturn]] void too_long() const {
    throw InputError(path_ + ":" + std::to_string(number_ + 1) + ": a line longer than " +
                     std::to_string(kMaxLineBytes) + " bytes");
  }

  InputFile& file_;
  const std::string& path_;
  std::string buffer_;
  std::size_t at_ = 0, number_ = 0;
  std::uintmax_t consumed_ = 0;
};

// A field as a number within a float's range: read as a double, then rounded (1e-50 is a number,
// 0 as a float; 1e50 is out of range). `what` is "FILE:LINE: COLUMN".
double parse_number(const std::string& field, const std::string& what) {
  double value = 0.0;
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  if (field.empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
    throw InputError(what + " '" + field + "' is not a number");
  if ((ec == std::errc::result_out_of_range && std::fabs(value) > 1.0) ||
      (std::isfinite(value) && std::fabs(value) > double(std::numeric_limits<float>::max())))
    throw InputError(what + " '" + field + "' is beyond a float's range");
  return value;
}

// The first line of a CSV file (after a UTF-8 byte order mark, as spreadsheets export): the header.
void read_header(LineReader& lines, const std::string& path, const std::string& what,
                 const std::string& expected) {
  std::string line;
  if (!lines.next(line)) throw InputError(path + ": empty " + what + " (expected header " + expected + ")");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
  if (split_fields(line) != split_fields(expected))
    throw InputError(path + ":1: header must be " + expected + " (found '" + line.substr(0, 40) + "')");
}

// Lines whose mean length sets the first estimate of a file's rays.
constexpr std::size_t kSampleLines = 1000;

}  // namespace

RayBatch load_rays_csv(const std::string& path, int tile_size) {
  // A regular file no larger than the budget: /dev/zero or a FIFO would read forever.
  InputFile file(path, "rays file", memory_budget());
  LineReader lines(file, path);
  // What a run holds per ray of the file (its columns as read, its batch with padding, hits,
  // references, images), asked of the budget for the rays the file's size suggests at the mean
  // line length so far: first after kSampleLines lines (or the whole file, if shorter), then again,
  // for a quarter more at least, whenever the rays read pass the rays asked for.
  const double bytes_per_ray = kBytesPerRayCsvRow + kBytesPerRay * padding_factor(tile_size);
  double asked = 0.0;
  const auto ask_budget = [&] {
    const double mean_line = double(lines.consumed()) / double(std::max<std::size_t>(lines.number(), 1));
    const double left = double(file.size()) - double(std::min<std::uintmax_t>(lines.consumed(), file.size()));
    const double rays = std::max(std::ceil(double(lines.number()) + left / std::max(mean_line, 1.0)),
                                 std::ceil(1.25 * asked));
    if (rays > double(kMaxCsvRays))
      throw InputError(path + ": about " + std::to_string((long long)rays) + " rays (" +
                       std::to_string(file.size()) + " bytes at " + std::to_string((long long)mean_line) +
                       " a line), more than the " + std::to_string(kMaxCsvRays) + " a rays file may have");
    check_memory_budget(bytes_per_ray * rays, path + " (about " + std::to_string((long long)rays) + " rays)");
    asked = rays;
  };
  const std::vector<std::string> expected = {"tx", "ty", "vx", "vy", "vz"};
  read_header(lines, path, "rays file", "tx,ty,vx,vy,vz");
  std::string line;
  std::vector<float> columns[5];
  // One line per pass; the budget bounds the lines a pass may add before it is asked again.
  while (lines.next(line)) {
    if (lines.number() == kSampleLines || (asked > 0.0 && double(lines.number()) > asked)) ask_budget();
    if (trim(line).empty()) continue;
    const std::vector<std::string> fields = split_fields(line);
    const std::string where = path + ":" + std::to_string(lines.number()) + ": ";
    if (fields.size() != 5)
      throw InputError(where + "expected 5 columns, found " + std::to_string(fields.size()));
    for (int c = 0; c < 5; ++c) columns[c].push_back(float(parse_number(fields[c], where + expected[c])));
  }
  if (asked == 0.0) ask_budget();  // a file of fewer than kSampleLines lines, now read whole
  if (columns[0].empty()) throw InputError(path + ": no rays after the header");
  try {
    return make_ray_list(columns[0], columns[1], columns[2], columns[3], columns[4], tile_size);
  } catch (const InputError& e) {
    // make_ray_list counts rays from 1: ray N is the file's line N + 1.
    throw InputError(path + ": " + e.what());
  }
}

std::vector<CameraPose> load_camera_poses(const std::string& path) {
  constexpr std::uintmax_t kMaxBytes = std::uintmax_t(kMaxCameraPoses + 1) * LineReader::kMaxLineBytes;
  InputFile file(path, "camera poses file", kMaxBytes);
  LineReader lines(file, path);
  const char* const columns[] = {"eye_x", "eye_y", "eye_z", "target_x", "target_y", "target_z",
                                 "up_x",  "up_y",  "up_z",  "fov",      "width",    "height"};
  std::string expected;
  for (const char* c : columns) expected += (expected.empty() ? "" : ",") + std::string(c);
  read_header(lines, path, "camera poses file", expected);
  std::vector<CameraPose> poses;
  for (std::string line; lines.next(line);) {
    if (trim(line).empty()) continue;
    const std::string where = path + ":" + std::to_string(lines.number()) + ": ";
    if (poses.size() == std::size_t(kMaxCameraPoses))
      throw InputError(where + "more than " + std::to_string(kMaxCameraPoses) + " poses");
    const std::vector<std::string> fields = split_fields(line);
    if (fields.size() != std::size(columns))
      throw InputError(where + "expected " + std::to_string(std::size(columns)) + " columns, found " +
                       std::to_string(fields.size()));
    double v[std::size(columns)];
    for (std::size_t c = 0; c < std::size(columns); ++c) {
      v[c] = parse_number(fields[c], where + columns[c]);
      if (!std::isfinite(v[c])) throw InputError(where + columns[c] + " '" + fields[c] + "' is not finite");
    }
    CameraPose p{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9], 0, 0, lines.number()};
    const double f[3] = {p.target[0] - p.eye[0], p.target[1] - p.eye[1], p.target[2] - p.eye[2]};
    const double cross[3] = {f[1] * p.up[2] - f[2] * p.up[1], f[2] * p.up[0] - f[0] * p.up[2],
                             f[0] * p.up[1] - f[1] * p.up[0]};
    const double f_len = std::hypot(f[0], f[1], f[2]), up_len = std::hypot(p.up[0], p.up[1], p.up[2]);
    if (!(p.eye[2] > 0)) throw InputError(where + "the eye must be above the surface (eye_z > 0)");
    if (!(f_len > 0)) throw InputError(where + "the target is at the eye");
    if (!(std::hypot(cross[0], cross[1], cross[2]) > 1e-9 * f_len * up_len))
      throw InputError(where + "up is zero or along the view direction");
    if (!(p.fov_degrees > 0 && p.fov_degrees < 180))
      throw InputError(where + "fov must be in (0, 180) degrees");
    for (int c : {10, 11}) {
      if (!(v[c] >= 1 && v[c] <= kMaxViewSide && v[c] == std::floor(v[c])))
        throw InputError(where + columns[c] + " must be a whole number of pixels in [1, " +
                         std::to_string(kMaxViewSide) + "]");
    }
    p.width = int(v[10]);
    p.height = int(v[11]);
    poses.push_back(p);
  }
  if (poses.empty()) throw InputError(path + ": no camera poses after the header");
  return poses;
}

}  // namespace heightmarch
