// heightmarch recommend: the recommendation of a measured run at a target of the user's, without
// measuring again: reads the run's measurements.json (its rows as typed candidates) and writes or
// prints the recommendation. Also the target options and recommendation.json of suite and claims.
#include "cli/recommend_command.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/commands.hpp"
#include "cli/run_directory.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "io/atomic_file.hpp"
#include "util/input_file.hpp"
#include "util/string_format.hpp"

namespace heightmarch::cli {

void add_target_options(CLI::App& command, RecommendationTarget& t) {
  std::vector<std::string> names;
  for (ErrorPercentile p : kErrorPercentiles) names.push_back(to_string(p));
  command
      .add_option_function<std::string>(
          "--percentile",
          [&t](const std::string& name) {
            for (ErrorPercentile p : kErrorPercentiles)
              if (to_string(p) == name) t.percentile = p;
          },
          "the uv error percentile the recommendation's error bound applies to: p50, p95, p99 or max")
      ->check(CLI::IsMember(names))
      ->default_str(to_string(t.percentile));
  command
      .add_option("--max-error", t.uv_error_texels,
                  "the recommendation's bound on that percentile, in texels")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command
      .add_option_function<double>(
          "--max-wrong-surface", [&t](double percent) { t.wrong_surface_rate = percent / 100.0; },
          "the recommendation's bound on the share of rays on a wrong surface (uv error above one texel), in "
          "percent")
      ->check(CLI::Range(0.0, 100.0))
      ->default_str(string_format("%g", 100.0 * t.wrong_surface_rate));
  command.add_option("--frames", t.frames, "frames the preprocessing (cone map, pyramid) is amortised over")
      ->check(CLI::Range(1, 1 << 30))
      ->capture_default_str();
}

void write_recommendation(const std::string& dir, const Recommendation& recommendation) {
  write_file_atomically(dir + "/recommendation.json", recommendation_json(recommendation));
  std::printf("%s", recommendation_text(recommendation).c_str());
}

namespace {

using Json = nlohmann::json;

// A parsed measurements.json holds about 4 times its size (measured on a full run's 5 MB file:
// 18 MB beside its text); 8 with the text and room, checked against the memory budget first.
constexpr double kJsonParseFactor = 8.0;
constexpr std::uintmax_t kMaxMeasurementsBytes = std::uintmax_t(1) << 36;
constexpr std::int64_t kMaxRays = std::int64_t(1) << 53;  // exact in a double
constexpr int kMaxJsonDepth = 64;  // a measurements.json nests 5 levels
// Bounds no measurement reaches, so that no figure made of them overflows: a repetition of a
// week; errors and samples per ray far beyond any map.
constexpr double kMaxSeconds = 7 * 24 * 3600.0;
constexpr double kLargest = 1e30;

// The fields of one row, each value checked for its type and range as it is taken: a bad value is
// one line naming the row and the field, never read as a figure.
class RowFields {
 public:
  RowFields(const Json& row, std::string where) : row_(row), where_(std::move(where)) {
    if (!row.is_object()) refuse("", "is not an object");
  }
  const Json& at(const Json& object, const std::string& key, const std::string& path) const {
    if (!object.is_object() || !object.contains(key)) refuse(path, "is missing");
    return object.at(key);
  }
  const Json& at(const std::string& key) const { return at(row_, key, key); }
  const Json& optional(const std::string& key) const {  // null where the row has no such field
    static const Json null;
    return row_.contains(key) ? row_.at(key) : null;
  }
  std::string text(const Json& v, const std::string& path) const {
    if (!v.is_string()) refuse(path, "is " + shown(v) + ", not a string");
    return v.get<std::string>();
  }
  // A finite number in [low, high] ((low, high] when `above`).
  double number(const Json& v, const std::string& path, double low, double high, bool above = false) const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) refuse(path, "is " + shown(v) + ", not a finite number");
    const double x = v.get<double>();
    if (x < low || (above && x == low) || x > high)
      refuse(path, "is " + shown(v) + ", not in " + (above ? "(" : "[") + string_format("%g, %g]", low, high));
    return x;
  }
  // An integer in low..high (low is never negative here). nlohmann keeps 1e20 a float and a
  // non-negative integer unsigned: neither is cast blindly.
  std::int64_t integer(const Json& v, const std::string& path, std::int64_t low, std::int64_t high) const {
    if (!v.is_number_integer()) refuse(path, "is " + shown(v) + ", not an integer");
    const bool in_range = v.is_number_unsigned()
                              ? v.get<std::uint64_t>() >= std::uint64_t(low) && v.get<std::uint64_t>() <= std::uint64_t(high)
                              : v.get<std::int64_t>() >= low && v.get<std::int64_t>() <= high;
    if (!in_range) refuse(path, "is " + shown(v) + ", not in " + std::to_string(low) + ".." + std::to_string(high));
    return v.get<std::int64_t>();
  }
  bool has_purpose(const std::string& name) const {
    const Json& purposes = at("purposes");
    if (!purposes.is_array()) refuse("purposes", "is not a list");
    for (const Json& p : purposes)
      if (text(p, "purposes") == name) return true;
    return false;
  }
  [[noreturn]] void refuse(const std::string& path, const std::string& why) const {
    throw InputError(where_ + (path.empty() ? "" : ": " + path) + ": " + why);
  }

 private:
  static std::string shown(const Json& v) {
    const std::string text = v.dump(-1, ' ', true);  // ASCII: a control character stays escaped
    return text.size() <= 60 ? text : text.substr(0, 60) + "...";
  }
  const Json& row_;
  std::string where_;
};

// A row of measurements.json as a candidate, or none for a row the recommendation does not read
// (the same rows candidates() takes from a run's Measurements). Format 1 named the percentiles uv_p99.
std::optional<Candidate> candidate_of(const RowFields& f, int format_version) {
  const std::string kind = f.text(f.at("kind"), "kind");
  if (kind != "trace" && kind != "glsl") return std::nullopt;
  if (!(f.has_purpose("matrix") || f.has_purpose("claims") || f.has_purpose("glsl"))) return std::nullopt;
  if (f.at("technique").is_null() || !f.optional("shader").is_null()) return std::nullopt;
  if (f.at("errors").is_null() || f.at("speed").is_null() || !f.at("failure").is_null()) return std::nullopt;
  if (f.text(f.at(f.at("view"), "kind", "view.kind"), "view.kind") != "default") return std::nullopt;
  const std::int64_t rays = f.integer(f.at("rays"), "rays", 0, kMaxRays);
  if (rays == 0) return std::nullopt;
  Candidate c;
  c.id = int(f.integer(f.at("id"), "id", 0, std::numeric_limits<int>::max()));
  const Json& hf = f.at("heightfield");
  c.heightfield = f.text(f.at(hf, "label", "heightfield.label"), "heightfield.label");
  c.depth_map_width = int(f.integer(f.at(hf, "width", "heightfield.width"), "heightfield.width", 1, 1 << 30));
  c.depth_map_height = int(f.integer(f.at(hf, "height", "heightfield.height"), "heightfield.height", 1, 1 << 30));
  const bool glsl = kind == "glsl";
  c.backend = {glsl ? RunKind::glsl : RunKind::trace,
               glsl ? Isa::scalar : isa_named(f.text(f.at("backend"), "backend")),
               int(f.integer(f.at("threads"), "threads", 1, 1 << 20))};
  // Its renderer's label; a run from before rows recorded it names none.
  if (const Json& gl = f.optional("gl"); glsl && !gl.is_null())
    c.backend.gl = printable(f.text(f.at(gl, "label", "gl.label"), "gl.label"));
  c.grid = !glsl && (f.has_purpose("matrix") || f.has_purpose("claims"));
  c.technique = parse_technique(f.text(f.at("technique"), "technique"));
  c.layers = parse_layer_spec(f.text(f.at("layers"), "layers"));
  const Json& errors = f.at("errors");
  for (ErrorPercentile p : kErrorPercentiles) {
    const std::string name = format_version >= 2 ? measure_name(p) : "uv_" + to_string(p);
    c.uv_error[int(p)] = f.number(f.at(errors, name, "errors." + name), "errors." + name, 0.0, kLargest);
  }
  c.wrong_surface_rate = f.number(f.at(errors, "wrong_surface_rate", "errors.wrong_surface_rate"),
                                  "errors.wrong_surface_rate", 0.0, 1.0);
  const Json& samples = f.at("samples_per_ray");
  c.samples_per_ray = samples.is_null() ? 0.0 : f.number(samples, "samples_per_ray", 0.0, kLargest);
  c.rays = std::size_t(rays);
  const Json& seconds = f.at(f.at("speed"), "seconds", "speed.seconds");
  if (!seconds.is_array() || seconds.empty()) f.refuse("speed.seconds", "is not a list of repetitions' seconds");
  for (const Json& s : seconds) c.seconds.push_back(f.number(s, "speed.seconds", 0.0, kMaxSeconds, true));
  if (const Json& p = f.optional("precompute_seconds"); !p.is_null())
    c.precompute_seconds = f.number(p, "precompute_seconds", 0.0, kMaxSeconds);
  return c;
}

std::vector<Candidate> read_candidates(const std::string& path) {
  const std::uintmax_t size = check_input_file(path, "measurements.json", kMaxMeasurementsBytes);
  check_memory_budget(double(size) * kJsonParseFactor, path + ": reading measurements.json");
  Json data;
  // Nesting beyond any measurements.json is refused as it is read: what reads a value (dump() in
  // an error line among them) recurses once per level.
  const auto shallow = [&path](int depth, Json::parse_event_t, Json&) {
    if (depth > kMaxJsonDepth) throw InputError(path + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    return true;
  };
  try {
    data = Json::parse(read_input_file(path, "measurements.json", kMaxMeasurementsBytes), shallow);
  } catch (const Json::exception& e) {  // nlohmann refuses NaN, Infinity and 1e400 as not JSON
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  static const Json null;
  const auto field = [&data](const char* key) -> const Json& {
    return data.is_object() && data.contains(key) ? data[key] : null;
  };
  int version = 0;
  if (field("format") == "heightmarch-measurements") {
    const Json& v = field("format_version");  // compared as JSON: 2^32 + 2 is no 2
    version = v.is_number_integer() && v >= 1 && v <= kMeasurementsFormatVersion ? v.get<int>() : 0;
  } else if (field("schema") == "heightmarch-measurements/1") {
    version = 1;
  }
  if (version < 1 || version > kMeasurementsFormatVersion)
    throw InputError(path + ": not a heightmarch measurements.json of format 1 to " +
                     std::to_string(kMeasurementsFormatVersion));
  const Json& rows = field("rows");
  if (!rows.is_array()) throw InputError(path + ": rows is not a list");
  std::vector<Candidate> out;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (auto c = candidate_of(RowFields(rows[i], path + ": rows[" + std::to_string(i) + "]"), version))
      out.push_back(std::move(*c));
  return out;
}

struct RecommendOptions {
  std::string measurements;
  RecommendationTarget target;
  std::string out;
  bool json = false;
};

}  // namespace

Command add_recommend_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "recommend",
      "the technique and layer count to ship at an error target, from a measured run (no new measurement)");
  auto o = std::make_shared<RecommendOptions>();
  command->add_option("measurements", o->measurements, "a run's measurements.json, or its directory")
      ->required();
  add_target_options(*command, o->target);
  command->add_option("--out", o->out,
                      "directory to write recommendation.json into (the run's own, to add or replace its "
                      "recommendation, or any other)");
  command->add_flag("--json", o->json, "print recommendation.json instead of the summary");
  return [o] {
    validate(o->target);
    std::optional<RunDirectory> out;  // checked and locked before the run is read
    if (!o->out.empty()) out.emplace(o->out, RunDirectory::Existing::beside);
    std::string path = o->measurements;
    if (std::filesystem::is_directory(path)) path += "/measurements.json";
    const Recommendation recommendation = recommend(read_candidates(path), o->target);
    if (recommendation.backends.empty())
      throw InputError(
          path + ": no timed technique rows of the technique x layers grid or the claims to recommend from");
    if (out) write_recommendation(out->path(), recommendation);
    std::printf(
        "%s", (o->json ? recommendation_json(recommendation) : recommendation_text(recommendation)).c_str());
    return 0;
  };
}

}  // namespace heightmarch::cli
