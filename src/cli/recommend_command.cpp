// heightmarch recommend: the recommendation of a measured run at a target of the user's, without
// measuring again: reads the run's measurements.json (its rows as typed candidates) and writes or
// prints the recommendation. Also the target options and recommendation.json of suite and claims.
#include "cli/recommend_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/gzip.hpp"
#include "cli/run_directory.hpp"
#include "experiment/plan_runner.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "io/atomic_file.hpp"
#include "io/json_writer.hpp"
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
          "the search error percentile the recommendation's error bound applies to: p50, p95, p99 or max "
          "(the "
          "search error: each ray's hit against the exact hit on the surface it reads)")
      ->check(CLI::IsMember(names))
      ->default_str(to_string(t.percentile));
  command
      .add_option_function<std::string>(
          "--unit", [&t](const std::string& name) { t.unit = parse_error_unit(name); },
          "the unit of the error bound and of a wrong hit: pixels (each ray's own pixel footprint: what a "
          "player sees; a wrong pixel is one more than a pixel off) or texels (of level 0; a wrong surface "
          "is "
          "one more than a texel off)")
      ->check(CLI::IsMember({"pixels", "texels"}))
      ->default_str(to_string(t.unit));
  command
      .add_option("--max-error", t.max_error, "the recommendation's bound on that percentile, in the unit")
      ->check(in_range(0))
      ->capture_default_str();
  command
      .add_option_function<double>(
          "--max-wrong,--max-wrong-surface", [&t](double percent) { t.max_wrong_rate = percent / 100.0; },
          "the recommendation's bound on the share of rays more than one unit off (a wrong pixel, or with "
          "--unit texels a wrong surface), in percent")
      ->check(in_range(0, 100))
      ->default_str(string_format("%g", 100.0 * t.max_wrong_rate));
  command.add_option("--frames", t.frames, "frames the preprocessing (cone map, pyramid) is amortised over")
      ->check(in_range(1, 1 << 30))
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
constexpr int kMaxJsonDepth = 64;                         // a measurements.json nests 5 levels
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
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      refuse(path, "is " + shown(v) + ", not a finite number");
    const double x = v.get<double>();
    if (x < low || (above && x == low) || x > high)
      refuse(path,
             "is " + shown(v) + ", not in " + (above ? "(" : "[") + string_format("%g, %g]", low, high));
    return x;
  }
  // An integer in low..high (low is never negative here). nlohmann keeps 1e20 a float and a
  // non-negative integer unsigned: neither is cast blindly.
  std::int64_t integer(const Json& v, const std::string& path, std::int64_t low, std::int64_t high) const {
    if (!v.is_number_integer()) refuse(path, "is " + shown(v) + ", not an integer");
    const bool in_range =
        v.is_number_unsigned()
            ? v.get<std::uint64_t>() >= std::uint64_t(low) && v.get<std::uint64_t>() <= std::uint64_t(high)
            : v.get<std::int64_t>() >= low && v.get<std::int64_t>() <= high;
    if (!in_range)
      refuse(path, "is " + shown(v) + ", not in " + std::to_string(low) + ".." + std::to_string(high));
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

// A row's errors in the target's unit as the recommendation reads them, each figure with its 95%
// interval; a run written before the intervals were (errors without confidence) gives each figure
// as its own interval. Format 1 named the uv error's percentiles uv_p99. A row from before the
// search error and the filter's bias were measured (format 3) read level 0 under bilinear
// filtering, whose search error is its uv error and whose bias is none; its trilinear rows and any
// row without pixel errors cannot be read so, and are refused.
Accuracy accuracy_of(const RowFields& f, int format_version, ErrorUnit unit) {
  const Json& errors = f.at("errors");
  const Json& confidence =
      errors.is_object() && errors.contains("confidence") ? errors.at("confidence") : Json();
  const auto interval = [&](const std::string& name, double value) -> Interval {
    if (!confidence.is_object() || !confidence.contains(name)) return {value, value};
    const Json& ci = confidence.at(name);
    const std::string path = "errors.confidence." + name;
    if (!ci.is_array() || ci.size() != 2) f.refuse(path, "is not a pair of numbers");
    return {f.number(ci[0], path, 0.0, kLargest), f.number(ci[1], path, 0.0, kLargest)};
  };
  const UnitDistributions d = distributions_in(unit);
  const bool searched = format_version >= 3;
  if (!searched) {
    if (unit == ErrorUnit::pixels)
      f.refuse("errors", "has no errors in pixels (measured before they were): read it with --unit texels");
    if (const Json& filter = f.optional("filter");
        !filter.is_null() && f.text(filter, "filter") != "bilinear")
      f.refuse("errors", "reads " + f.text(filter, "filter") +
                             " but was measured before the search error against the surface it reads was");
  }
  if (searched && errors.is_object() && errors.contains(d.search.measure("p99")) &&
      errors.at(d.search.measure("p99")).is_null())
    f.refuse("errors." + d.search.measure("p99"), "is null: the row's rays have no pixel grid");
  const auto figures = [&](const ErrorDistributionInfo& info, bool zero) {
    Figures out;
    for (ErrorPercentile p : kErrorPercentiles) {
      const std::string name = format_version >= 2 ? info.measure(to_string(p)) : "uv_" + to_string(p);
      out.values[int(p)] =
          zero ? 0.0 : f.number(f.at(errors, name, "errors." + name), "errors." + name, 0.0, kLargest);
      out.intervals[int(p)] = interval(info.measure(to_string(p)), out.values[int(p)]);
    }
    out.wrong_rate = zero ? 0.0
                          : f.number(f.at(errors, info.wrong_name, "errors." + info.wrong_name),
                                     "errors." + info.wrong_name, 0.0, 1.0);
    out.wrong_ci = interval(info.wrong_name, out.wrong_rate);
    return out;
  };
  Accuracy a;
  a.total = figures(d.total, false);
  a.search = searched ? figures(d.search, false) : a.total;
  a.bias = figures(d.bias, !searched);
  a.rays = std::size_t(f.integer(f.at("rays"), "rays", 0, kMaxRays));
  return a;
}

// What a row and its held-out twin share (everything but the view's seed), with a seed: a
// candidate's key at its seed + 1 is its twin's at its own.
std::string twin_key(const RowFields& f, std::int64_t seed) {
  Json key = Json::array();
  for (const char* field :
       {"kind", "backend", "threads", "technique", "layers", "refine", "scale", "wrap", "filter", "discard"})
    key.push_back(f.optional(field));
  key.push_back(f.at(f.at("heightfield"), "label", "heightfield.label"));
  Json view = f.at("view");
  if (!view.is_object()) f.refuse("view", "is not an object");
  view.erase("seed");
  view.erase("description");
  key.push_back(view);
  key.push_back(seed);
  return key.dump();
}

std::int64_t view_seed(const RowFields& f) {
  const Json& view = f.at("view");
  return view.is_object() && view.contains("seed") ? f.integer(view.at("seed"), "view.seed", 0, 1 << 30) : 0;
}

// A row of measurements.json as a candidate, or none for a row the recommendation does not read
// (the same rows candidates() takes from a run's Measurements): a technique row, timed, on the
// window (no sweep, rays file or fresh rays).
std::optional<Candidate> candidate_of(const RowFields& f, int format_version, ErrorUnit unit) {
  const std::string kind = f.text(f.at("kind"), "kind");
  if (kind != "trace" && kind != "glsl") return std::nullopt;
  if (!(f.has_purpose("matrix") || f.has_purpose("filters") || f.has_purpose("claims") ||
        f.has_purpose("glsl")))
    return std::nullopt;
  if (f.at("technique").is_null() || !f.optional("shader").is_null()) return std::nullopt;
  if (f.at("errors").is_null() || f.at("speed").is_null() || !f.at("failure").is_null()) return std::nullopt;
  const std::string view_kind = f.text(f.at(f.at("view"), "kind", "view.kind"), "view.kind");
  const Json& fresh = f.at("view").is_object() && f.at("view").contains("fresh_rays")
                          ? f.at("view").at("fresh_rays")
                          : Json();
  if (view_kind == "sweep" || view_kind == "rays" || !fresh.is_null()) return std::nullopt;
  const std::int64_t rays = f.integer(f.at("rays"), "rays", 0, kMaxRays);
  if (rays == 0) return std::nullopt;
  Candidate c;
  c.id = int(f.integer(f.at("id"), "id", 0, std::numeric_limits<int>::max()));
  const Json& hf = f.at("heightfield");
  c.heightfield = f.text(f.at(hf, "label", "heightfield.label"), "heightfield.label");
  c.depth_map_width = int(f.integer(f.at(hf, "width", "heightfield.width"), "heightfield.width", 1, 1 << 30));
  c.depth_map_height =
      int(f.integer(f.at(hf, "height", "heightfield.height"), "heightfield.height", 1, 1 << 30));
  const bool glsl = kind == "glsl";
  c.backend = {glsl ? RunKind::glsl : RunKind::trace,
               glsl ? Isa::scalar : isa_named(f.text(f.at("backend"), "backend")),
               int(f.integer(f.at("threads"), "threads", 1, 1 << 20)), "", Filter::bilinear};
  // Its renderer's label; a run from before rows recorded it names none.
  if (const Json& gl = f.optional("gl"); glsl && !gl.is_null())
    c.backend.gl = printable(f.text(f.at(gl, "label", "gl.label"), "gl.label"));
  c.grid = !glsl && (f.has_purpose("matrix") || f.has_purpose("filters") || f.has_purpose("claims"));
  c.technique = parse_technique(f.text(f.at("technique"), "technique"));
  c.layers = parse_layer_spec(f.text(f.at("layers"), "layers"));
  // Runs before filters read level 0.
  if (const Json& filter = f.optional("filter"); !filter.is_null())
    c.filter = parse_filter(f.text(filter, "filter"));
  c.backend.filter = c.filter;
  c.selection = accuracy_of(f, format_version, unit);
  const Json& samples = f.at("samples_per_ray");
  c.samples_per_ray = samples.is_null() ? 0.0 : f.number(samples, "samples_per_ray", 0.0, kLargest);
  c.rays = std::size_t(rays);
  const Json& seconds = f.at(f.at("speed"), "seconds", "speed.seconds");
  if (!seconds.is_array() || seconds.empty())
    f.refuse("speed.seconds", "is not a list of repetitions' seconds");
  for (const Json& s : seconds) c.seconds.push_back(f.number(s, "speed.seconds", 0.0, kMaxSeconds, true));
  if (const Json& p = f.optional("precompute_seconds"); !p.is_null())
    c.precompute_seconds = f.number(p, "precompute_seconds", 0.0, kMaxSeconds);
  return c;
}

// A run's measurements.json and its format version.
struct Measurements {
  Json data;
  int version = 0;
};

Measurements read_measurements(const std::string& path) {
  const std::uintmax_t size = check_input_file(path, "measurements.json", kMaxMeasurementsBytes);
  check_memory_budget(double(size) * kJsonParseFactor, path + ": reading measurements.json");
  Measurements m;
  Json& data = m.data;
  // Nesting beyond any measurements.json is refused as it is read: what reads a value (dump() in
  // an error line among them) recurses once per level.
  const auto shallow = [&path](int depth, Json::parse_event_t, Json&) {
    if (depth > kMaxJsonDepth)
      throw InputError(path + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    return true;
  };
  try {
    std::string text = read_input_file(path, "measurements.json", kMaxMeasurementsBytes);
    if (is_gzip(text)) text = gunzip(text, path, kMaxMeasurementsBytes, kJsonParseFactor);
    data = Json::parse(text, shallow);
  } catch (const Json::exception& e) {  // nlohmann refuses NaN, Infinity and 1e400 as not JSON
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  static const Json null;
  const auto field = [&data](const char* key) -> const Json& {
    return data.is_object() && data.contains(key) ? data[key] : null;
  };
  if (field("format") == "heightmarch-measurements") {
    const Json& v = field("format_version");  // compared as JSON: 2^32 + 2 is no 2
    m.version = v.is_number_integer() && v >= 1 && v <= kMeasurementsFormatVersion ? v.get<int>() : 0;
  } else if (field("schema") == "heightmarch-measurements/1") {
    m.version = 1;
  }
  if (m.version < 1 || m.version > kMeasurementsFormatVersion)
    throw InputError(path + ": not a heightmarch measurements.json of format 1 to " +
                     std::to_string(kMeasurementsFormatVersion));
  if (!field("rows").is_array()) throw InputError(path + ": rows is not a list");
  return m;
}

// The candidates of a run, each joined to its held-out twin (a row with the held-out purpose whose
// configuration is the candidate's on its window's next seed) where there is one.
std::vector<Candidate> read_candidates(const Measurements& m, const std::string& path, ErrorUnit unit) {
  const Json& rows = m.data["rows"];
  std::vector<Candidate> out;
  std::vector<std::string> keys;  // each candidate's twin's key
  std::map<std::string, std::pair<int, Accuracy>> held_out;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const RowFields f(rows[i], path + ": rows[" + std::to_string(i) + "]");
    if (auto c = candidate_of(f, m.version, unit)) {
      out.push_back(std::move(*c));
      keys.push_back(twin_key(f, view_seed(f) + 1));
    } else if (f.has_purpose("held-out") && !f.at("errors").is_null() && f.at("failure").is_null()) {
      held_out[twin_key(f, view_seed(f))] = {
          int(f.integer(f.at("id"), "id", 0, std::numeric_limits<int>::max())),
          accuracy_of(f, m.version, unit)};
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    if (const auto it = held_out.find(keys[i]); it != held_out.end()) {
      out[i].held_out_id = it->second.first;
      out[i].held_out = it->second.second;
    }
  return out;
}

// The outside check (docs/recommendation.md#the-outside-check): a row's configuration again, its
// window's rays replaced by fresh ones drawn like the window's (every azimuth and position uniform,
// the view angles from its own), for its accuracy.
Configuration fresh_rays_configuration(const RowFields& f, std::size_t rays, std::uint32_t seed) {
  Configuration c;
  const bool glsl = f.text(f.at("kind"), "kind") == "glsl";
  c.kind = glsl ? RunKind::glsl : RunKind::trace;
  c.isa = glsl ? Isa::scalar : isa_named(f.text(f.at("backend"), "backend"));
  c.threads = int(f.integer(f.at("threads"), "threads", 1, 1 << 20));
  const Json& hf = f.at("heightfield");
  c.heightfield = parse_heightfield(
      f.text(f.at(hf, "source", "heightfield.source"), "heightfield.source"),
      int(f.integer(f.at(hf, "width", "heightfield.width"), "heightfield.width", 1, kMaxDepthMapSide)));
  c.heightfield.name = f.text(f.at(hf, "label", "heightfield.label"), "heightfield.label");
  TechniqueParams& p = c.params;
  p.technique = parse_technique(f.text(f.at("technique"), "technique"));
  p.layers = layers_for(p.technique, parse_layer_spec(f.text(f.at("layers"), "layers")));
  p.refine = int(f.integer(f.at("refine"), "refine", 0, kMaxRefineSteps));
  p.scale = float(f.number(f.at("scale"), "scale", 0.0, 1.0, true));
  p.wrap = f.text(f.at("wrap"), "wrap") == "clamp" ? Wrap::clamp : Wrap::repeat;
  p.discard = f.at("discard").is_boolean() && f.at("discard").get<bool>();
  if (const Json& filter = f.optional("filter"); !filter.is_null())
    p.filter = parse_filter(f.text(filter, "filter"));
  validate(p);
  const Json& view = f.at("view");
  const std::string kind = f.text(f.at(view, "kind", "view.kind"), "view.kind");
  c.view = default_view(int(f.integer(f.at(view, "width", "view.width"), "view.width", 1, kMaxViewSide)),
                        int(f.integer(f.at(view, "height", "view.height"), "view.height", 1, kMaxViewSide)));
  if (kind == "tutorial") {
    c.view = seen_as(
        c.view,
        ViewSet::tutorial(int(f.integer(f.at(view, "views", "view.views"), "view.views", 1, kMaxSetViews))));
  } else if (kind == "poses") {
    c.view = seen_as(c.view, ViewSet::poses(f.text(f.at(view, "file", "view.file"), "view.file")));
  } else if (kind == "default") {
    c.view.near_degrees =
        float(f.number(f.at(view, "near_angle", "view.near_angle"), "view.near_angle", 0.0, kMaxViewDegrees));
    c.view.far_degrees =
        float(f.number(f.at(view, "far_angle", "view.far_angle"), "view.far_angle", 0.0, kMaxViewDegrees));
  } else {
    f.refuse("view.kind", "is " + kind + ": no window to draw fresh rays like");
  }
  c.view.fresh_rays = rays;
  c.view.seed = seed;
  c.timed = false;
  c.purposes = kPurposeCommand;
  return c;
}

// Every choice of the recommendation measured on fresh rays: per backend, the rows of its choice
// for all heightfields and on each, each configuration once; a table of the figures and their
// intervals against the target's bounds, and outside-check.json in `out` if given.
int outside_check(const Recommendation& recommendation, const Measurements& measurements, std::size_t rays,
                  std::uint32_t seed, const std::string& out) {
  std::map<int, const Json*> by_id;
  for (const Json& row : measurements.data.at("rows"))
    if (row.is_object() && row.contains("id") && row["id"].is_number_integer())
      by_id[row["id"].get<int>()] = &row;
  std::vector<Configuration> plan;
  struct Checked {
    std::string backend, heightfield, setting;
    std::size_t config;
  };
  std::vector<Checked> checked;
  for (const BackendRecommendation& b : recommendation.backends)
    for (const Answer& a : b.per_heightfield) {
      if (!a.choice) continue;
      const int id = a.choice->rows.front().id;
      const Configuration c = fresh_rays_configuration(
          RowFields(*by_id.at(id), "measurements.json: row " + std::to_string(id)), rays, seed);
      std::size_t index = std::find_if(plan.begin(), plan.end(),
                                       [&](const Configuration& p) { return p.same_measurement(c); }) -
                          plan.begin();
      if (index == plan.size()) plan.push_back(c);
      checked.push_back({b.backend.name(), a.heightfield, a.choice->label(), index});
    }
  MeasureOptions options;
  options.repetitions = 1;
  options.min_seconds = 0;
  const MeasuredPlan run = measure_plan(plan, options);
  const RecommendationTarget& t = recommendation.target;
  std::string text = string_format(
      "Outside check at %s: each choice on %zu fresh rays (seed %u: every azimuth and entry "
      "point uniform, the view angles drawn from the window's), against the exact "
      "intersection; 95%% intervals:\n",
      describe(t).c_str(), rays, seed);
  JsonWriter json;
  // Format 2: the target's measures (the search error in its unit) under their names.
  json.begin_object().value("format", "heightmarch-outside-check").value("format_version", 2);
  json.value("target", describe(t)).value("rays", rays).value("seed", (long long)seed).begin_array("checks");
  int failed = 0;
  for (const Checked& k : checked) {
    const Measurement& m = run.rows[k.config];
    if (!m.errors) throw InputError(k.heightfield + " " + k.setting + ": not measured (" + m.failure + ")");
    const Accuracy a = accuracy_of(*m.errors, t.unit);
    const double value = a.error(t.percentile);
    const Interval ci = a.error_ci(t.percentile), wrong_ci = a.search.wrong_ci;
    const bool meets = heightmarch::meets(a, t);
    const bool consistent = ci.low <= t.max_error && wrong_ci.low <= t.max_wrong_rate;
    failed += !consistent;
    const UnitDistributions d = distributions_in(t.unit);
    text += string_format("  %s, %s: %s: %s %.3g (%.3g-%.3g) %s, %s %.3g%% (%.3g-%.3g%%): %s\n",
                          k.backend.c_str(), k.heightfield.c_str(), k.setting.c_str(),
                          to_string(t.percentile).c_str(), value, ci.low, ci.high, to_string(t.unit).c_str(),
                          t.unit == ErrorUnit::pixels ? "wrong pixel" : "wrong surface", 100 * a.wrong_rate(),
                          100 * wrong_ci.low, 100 * wrong_ci.high,
                          meets        ? "meets the target"
                          : consistent ? "on the bound (within the 95% interval)"
                                       : "misses the target");
    json.begin_object()
        .value("backend", k.backend)
        .value("heightfield", k.heightfield)
        .value("setting", k.setting);
    json.value("view", describe(m.config.view)).value(measure_name(t), value);
    json.begin_array(measure_name(t) + "_ci").value("", ci.low).value("", ci.high).end_array();
    json.value(d.search.wrong_name, a.wrong_rate());
    json.begin_array(d.search.wrong_ci_name()).value("", wrong_ci.low).value("", wrong_ci.high).end_array();
    json.value("meets", meets).value("within_interval", consistent).end_object();
  }
  json.end_array().value("missed", failed).end_object();
  std::fputs(text.c_str(), stdout);
  if (!out.empty()) write_file_atomically(out + "/outside-check.json", json.str() + "\n");
  return failed ? 1 : 0;
}

struct RecommendOptions {
  std::string measurements;
  RecommendationTarget target;
  std::string out;
  bool json = false;
  std::size_t outside_rays = 0;
  std::uint32_t outside_seed = 1;
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
  command
      ->add_option(
          "--outside-check", o->outside_rays,
          "also trace each choice on this many fresh rays per map (every azimuth and entry point uniform, "
          "the view angles drawn from the run's window) against the exact intersection, and say whether it "
          "meets the target within its 95% interval (exit 1 where one misses); with --out, "
          "outside-check.json")
      ->check(CLI::Range(std::size_t(1000), std::size_t(64) << 20));
  command->add_option("--outside-seed", o->outside_seed, "the seed of the outside check's rays")
      ->check(CLI::Range(1, 1 << 30))
      ->capture_default_str();
  return [o] {
    validate(o->target);
    std::optional<RunDirectory> out;  // checked and locked before the run is read
    if (!o->out.empty()) out.emplace(o->out, RunDirectory::Existing::beside);
    std::string path = o->measurements;
    std::error_code ec;  // a path the system cannot look up (a name too long) is no directory
    if (std::filesystem::is_directory(path, ec)) {
      path += "/measurements.json";
      if (!std::filesystem::exists(path, ec) && std::filesystem::exists(path + ".gz", ec)) path += ".gz";
    }
    const Measurements measurements = read_measurements(path);
    const Recommendation recommendation =
        recommend(read_candidates(measurements, path, o->target.unit), o->target);
    if (recommendation.backends.empty())
      throw InputError(
          path + ": no timed technique rows of the technique x layers grid or the claims to recommend from");
    if (out) write_recommendation(out->path(), recommendation);
    std::printf(
        "%s", (o->json ? recommendation_json(recommendation) : recommendation_text(recommendation)).c_str());
    if (o->outside_rays)
      return outside_check(recommendation, measurements, o->outside_rays, o->outside_seed,
                           out ? out->path() : "");
    return 0;
  };
}

}  // namespace heightmarch::cli
