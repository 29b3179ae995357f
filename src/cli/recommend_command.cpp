// heightmarch recommend: the recommendation of a measured run at a target of the user's, without
// measuring again: reads the run's measurements.json (its rows as typed candidates) and writes or
// prints the recommendation. Also the target options and recommendation.json of suite and claims.
#include "cli/recommend_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/common_options.hpp"
#include "cli/run_directory.hpp"
#include "experiment/run_outputs.hpp"
#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
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
      ->check(in_range(0))
      ->capture_default_str();
  command
      .add_option_function<double>(
          "--max-wrong-surface", [&t](double percent) { t.wrong_surface_rate = percent / 100.0; },
          "the recommendation's bound on the share of rays on a wrong surface (uv error above one texel), in "
          "percent")
      ->check(in_range(0, 100))
      ->default_str(string_format("%g", 100.0 * t.wrong_surface_rate));
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

// A row of measurements.json as a candidate, or none for a row the recommendation does not read
// (the same rows candidates() takes from a run's Measurements). Format 1 named the percentiles uv_p99.
std::optional<Candidate> candidate_of(const Json& row, int format_version) {
  const std::string kind = row.at("kind").get<std::string>();
  if (kind != "trace" && kind != "glsl") return std::nullopt;
  if (!(has_purpose(row, "matrix") || has_purpose(row, "claims") || has_purpose(row, "glsl")))
    return std::nullopt;
  if (row.at("technique").is_null() || !row.value("shader", Json()).is_null()) return std::nullopt;
  if (row.at("errors").is_null() || row.at("speed").is_null() || !row.at("failure").is_null())
    return std::nullopt;
  if (row.at("view").at("kind").get<std::string>() != "default" || row.at("rays").get<std::size_t>() == 0)
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
  const Json& errors = row.at("errors");
  for (ErrorPercentile p : kErrorPercentiles)
    c.uv_error[int(p)] =
        errors.at(format_version >= 2 ? measure_name(p) : "uv_" + to_string(p)).get<double>();
  c.wrong_surface_rate = errors.at("wrong_surface_rate").get<double>();
  c.samples_per_ray = row.at("samples_per_ray").is_null() ? 0.0 : row.at("samples_per_ray").get<double>();
  c.rays = row.at("rays").get<std::size_t>();
  c.seconds = row.at("speed").at("seconds").get<std::vector<double>>();
  for (double s : c.seconds)
    if (!(std::isfinite(s) && s > 0)) throw InputError("a repetition's seconds must be positive");
  if (const Json& p = row.value("precompute_seconds", Json()); !p.is_null())
    c.precompute_seconds = p.get<double>();
  return c;
}

std::vector<Candidate> read_candidates(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read it");
  Json data;
  try {
    data = Json::parse(in);
  } catch (const Json::exception& e) {
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  int version = 0;
  if (data.is_object() && data.value("format", "") == "heightmarch-measurements" &&
      data.contains("format_version"))
    version = data["format_version"].is_number_integer() ? data["format_version"].get<int>() : 0;
  else if (data.is_object() && data.value("schema", "") == "heightmarch-measurements/1")
    version = 1;
  if (version < 1 || version > kMeasurementsFormatVersion)
    throw InputError(path + ": not a heightmarch measurements.json of format 1 to " +
                     std::to_string(kMeasurementsFormatVersion));
  std::vector<Candidate> out;
  const Json& rows = data.at("rows");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    try {
      if (auto c = candidate_of(rows[i], version)) out.push_back(std::move(*c));
    } catch (const Json::exception& e) {
      throw InputError(path + ": row " + std::to_string(i) + ": " + e.what());
    } catch (const InputError& e) {
      throw InputError(path + ": row " + std::to_string(i) + ": " + e.what());
    }
  }
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
