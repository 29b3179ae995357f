// heightmarch recommend: the recommendation of a measured run at a target of the user's, without
// measuring again: reads the run's measurements.json (its rows as typed candidates) and writes or
// prints the recommendation. Also the target options and recommendation.json of suite and claims.
#include "cli/recommend_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/run_directory.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "experiment/plan_runner.hpp"
#include "io/atomic_file.hpp"
#include "io/json_writer.hpp"
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

// The ISA named in a row, whichever machine measured it (no check that this CPU runs it).
Isa isa_named(const std::string& name) {
  for (Isa isa : all_isas())
    if (to_string(isa) == name) return isa;
  throw InputError("backend '" + name + "' is no ISA of " + isa_names());
}

bool has_purpose(const Json& row, const std::string& name) {
  for (const Json& p : row.at("purposes"))
    if (p.get<std::string>() == name) return true;
  return false;
}

// A row's errors as the recommendation reads them; a run written before the intervals were
// (measurements.json without errors.confidence) gives each figure as its own interval. Format 1
// named the percentiles uv_p99.
Accuracy accuracy_of(const Json& row, int format_version) {
  const Json& errors = row.at("errors");
  const Json confidence = errors.value("confidence", Json::object());
  Accuracy a;
  for (ErrorPercentile p : kErrorPercentiles) {
    const double value = errors.at(format_version >= 2 ? measure_name(p) : "uv_" + to_string(p)).get<double>();
    a.uv_error[int(p)] = value;
    a.uv_error_ci[int(p)] = {value, value};
    if (const auto ci = confidence.find(measure_name(p)); ci != confidence.end())
      a.uv_error_ci[int(p)] = {ci->at(0).get<double>(), ci->at(1).get<double>()};
  }
  a.wrong_surface_rate = errors.at("wrong_surface_rate").get<double>();
  a.wrong_surface_ci = {a.wrong_surface_rate, a.wrong_surface_rate};
  if (const auto ci = confidence.find("wrong_surface_rate"); ci != confidence.end())
    a.wrong_surface_ci = {ci->at(0).get<double>(), ci->at(1).get<double>()};
  a.rays = row.at("rays").get<std::size_t>() - errors.at("discarded").get<std::size_t>();
  return a;
}

// What a row and its held-out twin share (everything but the view's seed), with a seed: a
// candidate's key at its seed + 1 is its twin's at its own.
std::string twin_key(const Json& row, long long seed) {
  Json key = Json::array();
  for (const char* field : {"kind", "backend", "threads", "technique", "layers", "refine", "scale", "wrap", "discard"})
    key.push_back(row.value(field, Json()));
  key.push_back(row.at("heightfield").at("label"));
  Json view = row.at("view");
  view.erase("seed");
  view.erase("description");
  key.push_back(view);
  key.push_back(seed);
  return key.dump();
}

// A row of measurements.json as a candidate, or none for a row the recommendation does not read
// (the same rows candidates() takes from a run's Measurements).
std::optional<Candidate> candidate_of(const Json& row, int format_version) {
  const std::string kind = row.at("kind").get<std::string>();
  if (kind != "trace" && kind != "glsl") return std::nullopt;
  if (!(has_purpose(row, "matrix") || has_purpose(row, "claims") || has_purpose(row, "glsl")))
    return std::nullopt;
  if (row.at("technique").is_null() || !row.value("shader", Json()).is_null()) return std::nullopt;
  if (row.at("errors").is_null() || row.at("speed").is_null() || !row.at("failure").is_null())
    return std::nullopt;
  const Json& view = row.at("view");
  const std::string view_kind = view.at("kind").get<std::string>();
  if (view_kind == "sweep" || view_kind == "rays" || !view.value("fresh_rays", Json()).is_null() ||
      row.at("rays").get<std::size_t>() == 0)
    return std::nullopt;
  Candidate c;
  c.id = row.at("id").get<int>();
  c.heightfield = row.at("heightfield").at("label").get<std::string>();
  c.depth_map_width = row.at("heightfield").at("width").get<int>();
  c.depth_map_height = row.at("heightfield").at("height").get<int>();
  const bool glsl = kind == "glsl";
  c.backend = {glsl ? RunKind::glsl : RunKind::trace,
               glsl ? Isa::scalar : isa_named(row.at("backend").get<std::string>()),
               row.at("threads").get<int>()};
  c.grid = !glsl && (has_purpose(row, "matrix") || has_purpose(row, "claims"));
  c.technique = parse_technique(row.at("technique").get<std::string>());
  c.layers = parse_layer_spec(row.at("layers").get<std::string>());
  c.selection = accuracy_of(row, format_version);
  c.samples_per_ray = row.at("samples_per_ray").is_null() ? 0.0 : row.at("samples_per_ray").get<double>();
  c.rays = row.at("rays").get<std::size_t>();
  c.seconds = row.at("speed").at("seconds").get<std::vector<double>>();
  for (double s : c.seconds)
    if (!(std::isfinite(s) && s > 0)) throw InputError("a repetition's seconds must be positive");
  if (const Json& p = row.value("precompute_seconds", Json()); !p.is_null())
    c.precompute_seconds = p.get<double>();
  return c;
}

// A run's measurements.json and its format version.
struct Measurements {
  Json data;
  int version = 0;
};

Measurements read_measurements(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read it");
  Measurements m;
  Json& data = m.data;
  try {
    data = Json::parse(in);
  } catch (const Json::exception& e) {
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  if (data.is_object() && data.value("format", "") == "heightmarch-measurements" &&
      data.contains("format_version"))
    m.version = data["format_version"].is_number_integer() ? data["format_version"].get<int>() : 0;
  else if (data.is_object() && data.value("schema", "") == "heightmarch-measurements/1")
    m.version = 1;
  if (m.version < 1 || m.version > kMeasurementsFormatVersion)
    throw InputError(path + ": not a heightmarch measurements.json of format 1 to " +
                     std::to_string(kMeasurementsFormatVersion));
  return m;
}

std::vector<Candidate> read_candidates(const Measurements& measurements, const std::string& path) {
  const Json& data = measurements.data;
  const int version = measurements.version;
  std::vector<Candidate> out;
  std::vector<std::string> keys;  // each candidate's twin's key
  std::map<std::string, std::pair<int, Accuracy>> held_out;
  const Json& rows = data.at("rows");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    try {
      const Json& row = rows[i];
      const long long seed = row.at("view").value("seed", 0LL);
      if (auto c = candidate_of(row, version)) {
        out.push_back(std::move(*c));
        keys.push_back(twin_key(row, seed + 1));
      } else if (has_purpose(row, "held-out") && !row.at("errors").is_null() && row.at("failure").is_null()) {
        held_out[twin_key(row, seed)] = {row.at("id").get<int>(), accuracy_of(row, version)};
      }
    } catch (const Json::exception& e) {
      throw InputError(path + ": row " + std::to_string(i) + ": " + e.what());
    } catch (const InputError& e) {
      throw InputError(path + ": row " + std::to_string(i) + ": " + e.what());
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
Configuration fresh_rays_configuration(const Json& row, std::size_t rays, std::uint32_t seed) {
  Configuration c;
  const bool glsl = row.at("kind").get<std::string>() == "glsl";
  c.kind = glsl ? RunKind::glsl : RunKind::trace;
  c.isa = glsl ? Isa::scalar : isa_named(row.at("backend").get<std::string>());
  c.threads = row.at("threads").get<int>();
  const Json& hf = row.at("heightfield");
  c.heightfield = parse_heightfield(hf.at("source").get<std::string>(), hf.at("width").get<int>());
  c.heightfield.name = hf.at("label").get<std::string>();
  TechniqueParams& p = c.params;
  p.technique = parse_technique(row.at("technique").get<std::string>());
  p.layers = layers_for(p.technique, parse_layer_spec(row.at("layers").get<std::string>()));
  p.refine = row.at("refine").get<int>();
  p.scale = row.at("scale").get<float>();
  p.wrap = row.at("wrap").get<std::string>() == "clamp" ? Wrap::clamp : Wrap::repeat;
  p.discard = row.at("discard").get<bool>();
  validate(p);
  const Json& view = row.at("view");
  const std::string kind = view.at("kind").get<std::string>();
  c.view = parse_view("default", view.at("width").get<int>(), view.at("height").get<int>());
  if (kind == "tutorial") {
    apply_views("tutorial:" + std::to_string(view.at("views").get<int>()), c.view);
  } else if (kind == "poses") {
    apply_views(view.at("file").get<std::string>(), c.view);
  } else if (kind == "default") {
    c.view.near_degrees = view.at("near_angle").get<float>();
    c.view.far_degrees = view.at("far_angle").get<float>();
  } else {
    throw InputError("a row on a " + kind + " view has no window to draw fresh rays like");
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
  for (const Json& row : measurements.data.at("rows")) by_id[row.at("id").get<int>()] = &row;
  std::vector<Configuration> plan;
  struct Checked {
    std::string backend, heightfield, setting;
    std::size_t config;
  };
  std::vector<Checked> checked;
  for (const BackendRecommendation& b : recommendation.backends)
    for (const Answer& a : b.per_heightfield) {
      if (!a.choice) continue;
      const Configuration c = fresh_rays_configuration(*by_id.at(a.choice->rows.front().id), rays, seed);
      std::size_t index = std::find_if(plan.begin(), plan.end(), [&](const Configuration& p) { return p.same_measurement(c); }) - plan.begin();
      if (index == plan.size()) plan.push_back(c);
      checked.push_back({b.backend.name(), a.heightfield, a.choice->label(), index});
    }
  MeasureOptions options;
  options.repetitions = 1;
  options.min_seconds = 0;
  const MeasuredPlan run = measure_plan(plan, options);
  const RecommendationTarget& t = recommendation.target;
  std::string text = string_format("Outside check at %s: each choice on %zu fresh rays (seed %u: every azimuth and entry "
                                   "point uniform, the view angles drawn from the window's), against the exact "
                                   "intersection; 95%% intervals:\n",
                                   describe(t).c_str(), rays, seed);
  JsonWriter json;
  json.begin_object().value("format", "heightmarch-outside-check").value("format_version", 1);
  json.value("target", describe(t)).value("rays", rays).value("seed", (long long)seed).begin_array("checks");
  int failed = 0;
  for (const Checked& k : checked) {
    const Measurement& m = run.rows[k.config];
    if (!m.errors) throw InputError(k.heightfield + " " + k.setting + ": not measured (" + m.failure + ")");
    const Accuracy a = accuracy_of(*m.errors);
    const double value = a.error(t.percentile);
    const Interval ci = a.error_ci(t.percentile);
    const bool meets = value <= t.uv_error_texels && a.wrong_surface_rate <= t.wrong_surface_rate;
    const bool consistent = ci.low <= t.uv_error_texels && a.wrong_surface_ci.low <= t.wrong_surface_rate;
    failed += !consistent;
    text += string_format("  %s, %s: %s: %s %.3g (%.3g-%.3g) texel, wrong surface %.3g%% (%.3g-%.3g%%): %s\n",
                          k.backend.c_str(), k.heightfield.c_str(), k.setting.c_str(), to_string(t.percentile).c_str(),
                          value, ci.low, ci.high, 100 * a.wrong_surface_rate, 100 * a.wrong_surface_ci.low,
                          100 * a.wrong_surface_ci.high,
                          meets ? "meets the target" : consistent ? "on the bound (within the 95% interval)"
                                                                   : "misses the target");
    json.begin_object().value("backend", k.backend).value("heightfield", k.heightfield).value("setting", k.setting);
    json.value("view", describe(m.config.view)).value(measure_name(t.percentile), value);
    json.begin_array(measure_name(t.percentile) + "_ci").value("", ci.low).value("", ci.high).end_array();
    json.value("wrong_surface_rate", a.wrong_surface_rate);
    json.begin_array("wrong_surface_ci").value("", a.wrong_surface_ci.low).value("", a.wrong_surface_ci.high).end_array();
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
  std::size_t outside_rays = 0;
  std::uint32_t outside_seed = 1;
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
  command
      ->add_option("--outside-check", o->outside_rays,
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
    if (std::filesystem::is_directory(path)) path += "/measurements.json";
    const Measurements measurements = read_measurements(path);
    const Recommendation recommendation = recommend(read_candidates(measurements, path), o->target);
    if (recommendation.backends.empty())
      throw InputError(
          path + ": no timed technique rows of the technique x layers grid or the claims to recommend from");
    if (out) write_recommendation(out->path(), recommendation);
    std::printf(
        "%s", (o->json ? recommendation_json(recommendation) : recommendation_text(recommendation)).c_str());
    if (o->outside_rays)
      return outside_check(recommendation, measurements, o->outside_rays, o->outside_seed, out ? out->path() : "");
    return 0;
  };
}

}  // namespace heightmarch::cli
