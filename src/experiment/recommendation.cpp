// The recommendation: per declared backend, the fastest configuration meeting the target on each
// heightfield and on all of them, ranked by measured time per ray, never by samples per ray.
#include "experiment/recommendation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "heightmarch/error.hpp"
#include "io/json_writer.hpp"
#include "io/markdown.hpp"
#include "util/string_format.hpp"

namespace heightmarch {

std::string to_string(ErrorPercentile p) {
  switch (p) {
    case ErrorPercentile::p50:
      return "p50";
    case ErrorPercentile::p95:
      return "p95";
    case ErrorPercentile::p99:
      return "p99";
    case ErrorPercentile::max:
      return "max";
  }
  return "?";
}

std::string measure_name(ErrorPercentile p) { return "uv_error_" + to_string(p); }

void validate(const RecommendationTarget& t) {
  if (!(std::isfinite(t.uv_error_texels) && t.uv_error_texels >= 0))
    throw InputError("the target's uv error bound must be a number of texels >= 0");
  if (!(std::isfinite(t.wrong_surface_rate) && t.wrong_surface_rate >= 0 && t.wrong_surface_rate <= 1))
    throw InputError("the target's wrong-surface bound must be a share in [0, 1] (a percentage in [0, 100])");
  if (t.frames < 1) throw InputError("the frames preprocessing is amortised over must be at least 1");
}

std::string describe(const RecommendationTarget& t) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s <= %g texel, wrong surface <= %g%%", to_string(t.percentile).c_str(),
                t.uv_error_texels, 100.0 * t.wrong_surface_rate);
  return buf;
}

std::string RecommendationBackend::backend() const { return kind == RunKind::glsl ? "glsl" : to_string(isa); }

std::string RecommendationBackend::name() const {
  return backend() + ", " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
}

std::vector<Candidate> candidates(const std::vector<Measurement>& rows) {
  std::vector<Candidate> out;
  for (const Measurement& m : rows) {
    const Configuration& c = m.config;
    if (!(c.purposes & (kPurposeMatrix | kPurposeClaims | kPurposeGlsl)) ||
        !(c.kind == RunKind::trace || c.kind == RunKind::glsl) || !c.has_technique() || !m.errors ||
        m.seconds.empty() || !m.failure.empty() || c.view.kind != ViewSpec::Kind::perspective || m.rays == 0)
      continue;
    Candidate k;
    k.id = m.id;
    k.heightfield = c.heightfield.label();
    k.depth_map_width = m.depth_map_width;
    k.depth_map_height = m.depth_map_height;
    k.backend = {c.kind, c.kind == RunKind::trace ? c.isa : Isa::scalar, c.threads};
    k.grid = c.purposes & (kPurposeMatrix | kPurposeClaims);
    k.technique = c.params.technique;
    k.layers = c.params.layers;
    const ErrorSummary& e = *m.errors;
    k.uv_error[int(ErrorPercentile::p50)] = e.p50;
    k.uv_error[int(ErrorPercentile::p95)] = e.p95;
    k.uv_error[int(ErrorPercentile::p99)] = e.p99;
    k.uv_error[int(ErrorPercentile::max)] = e.max;
    k.wrong_surface_rate = e.wrong_surface_rate;
    k.samples_per_ray = m.samples_known ? double(m.samples) / double(m.rays) : 0.0;
    k.rays = m.rays;
    k.seconds = m.seconds;
    k.precompute_seconds = m.precompute_seconds;
    out.push_back(std::move(k));
  }
  return out;
}

std::string Pick::label() const {
  return to_string(technique) + (info(technique).layered ? " " + to_string(layers) : std::string());
}

namespace {

bool meets(const Candidate& c, const RecommendationTarget& t) {
  return c.error(t.percentile) <= t.uv_error_texels && c.wrong_surface_rate <= t.wrong_surface_rate;
}

// How far a row is from the target: the larger of its two measures over their bounds (1: on it).
double shortfall(const Candidate& c, const RecommendationTarget& t) {
  const auto over = [](double value, double bound) {
    return bound > 0 ? value / bound : (value > 0 ? HUGE_VAL : 0.0);
  };
  return std::max(over(c.error(t.percentile), t.uv_error_texels),
                  over(c.wrong_surface_rate, t.wrong_surface_rate));
}

// A setting's rows (one per heightfield) and its time per round: the mean seconds per ray over
// them. Rounds pair within a heightfield (its rows are timed in the same rounds); across
// heightfields, round i of each is summed.
Pick make_pick(std::vector<Candidate> rows) {
  Pick p;
  p.technique = rows.front().technique;
  p.layers = rows.front().layers;
  std::size_t rounds = rows.front().seconds.size();
  for (const Candidate& r : rows) rounds = std::min(rounds, r.seconds.size());
  p.seconds_per_ray.assign(rounds, 0.0);
  for (const Candidate& r : rows)
    for (std::size_t i = 0; i < rounds; ++i)
      p.seconds_per_ray[i] += r.seconds[i] / double(r.rays) / double(rows.size());
  p.rows = std::move(rows);
  return p;
}

Spread ratio_per_round(const Pick& slower, const Pick& faster) {
  std::vector<double> ratios;
  for (std::size_t i = 0; i < std::min(slower.seconds_per_ray.size(), faster.seconds_per_ray.size()); ++i)
    ratios.push_back(slower.seconds_per_ray[i] / faster.seconds_per_ray[i]);
  return spread_of(ratios);
}

// settings: each a setting's rows on the heightfields asked for (one row each).
Answer answer(const std::string& heightfield, const std::vector<std::vector<Candidate>>& settings,
              const RecommendationTarget& target) {
  Answer a;
  a.heightfield = heightfield;
  a.settings = int(settings.size());
  std::vector<Pick> meeting;
  const std::vector<Candidate>* closest = nullptr;
  double closest_shortfall = HUGE_VAL;
  for (const std::vector<Candidate>& rows : settings) {
    double worst = 0;
    for (const Candidate& r : rows) worst = std::max(worst, shortfall(r, target));
    if (std::all_of(rows.begin(), rows.end(), [&](const Candidate& r) { return meets(r, target); }))
      meeting.push_back(make_pick(rows));
    else if (worst < closest_shortfall)
      closest = &rows, closest_shortfall = worst;
  }
  a.meeting = int(meeting.size());
  std::stable_sort(meeting.begin(), meeting.end(),
                   [](const Pick& x, const Pick& y) { return x.time().median < y.time().median; });
  if (!meeting.empty()) a.choice = meeting[0];
  if (meeting.size() > 1) {
    a.runner_up = meeting[1];
    a.runner_up_ratio = ratio_per_round(meeting[1], meeting[0]);
  }
  if (meeting.empty() && closest) a.closest = make_pick(*closest);
  return a;
}

bool same_setting(const Candidate& a, const Candidate& b) {
  return a.technique == b.technique && a.layers == b.layers;
}

// The declared backends: the grid's CPU backends, then GLSL at each of their thread counts.
std::vector<RecommendationBackend> declared_backends(const std::vector<Candidate>& all) {
  std::vector<RecommendationBackend> out;
  const auto add = [&](const RecommendationBackend& b) {
    if (std::find(out.begin(), out.end(), b) == out.end()) out.push_back(b);
  };
  for (const Candidate& c : all)
    if (c.grid && c.backend.kind == RunKind::trace) add(c.backend);
  const std::size_t cpu = out.size();
  for (std::size_t i = 0; i < cpu; ++i)
    for (const Candidate& c : all)
      if (c.backend.kind == RunKind::glsl && c.backend.threads == out[i].threads) add(c.backend);
  return out;
}

}  // namespace

Recommendation recommend(const std::vector<Candidate>& all, const RecommendationTarget& target) {
  validate(target);
  Recommendation out;
  out.target = target;
  for (const RecommendationBackend& backend : declared_backends(all)) {
    std::vector<Candidate> rows;
    for (const Candidate& c : all)
      if (c.backend == backend) rows.push_back(c);
    std::vector<std::string> heightfields;
    for (const Candidate& c : rows)
      if (std::find(heightfields.begin(), heightfields.end(), c.heightfield) == heightfields.end())
        heightfields.push_back(c.heightfield);
    BackendRecommendation b;
    b.backend = backend;
    // A setting for all heightfields: one measured on every one of them, in first-seen order.
    std::vector<std::vector<Candidate>> everywhere;
    for (const std::string& hf : heightfields) {
      std::vector<std::vector<Candidate>> settings;
      for (const Candidate& c : rows)
        if (c.heightfield == hf) settings.push_back({c});
      b.per_heightfield.push_back(answer(hf, settings, target));
    }
    for (const Candidate& first : rows) {
      if (first.heightfield != heightfields.front()) continue;
      std::vector<Candidate> setting;
      for (const std::string& hf : heightfields) {
        const auto it = std::find_if(rows.begin(), rows.end(), [&](const Candidate& c) {
          return c.heightfield == hf && same_setting(c, first);
        });
        if (it != rows.end()) setting.push_back(*it);
      }
      if (setting.size() == heightfields.size()) everywhere.push_back(std::move(setting));
    }
    b.all_heightfields = answer("", everywhere, target);
    out.backends.push_back(std::move(b));
  }
  return out;
}

namespace {

void write_spread(JsonWriter& json, const std::string& key, const Spread& s, double scale = 1.0) {
  json.begin_object(key)
      .value("median", s.median * scale)
      .value("min", s.min * scale)
      .value("max", s.max * scale)
      .end_object();
}

// A pick: its setting, its time, and per heightfield the row with its measures, the time of one
// frame (one trace of the view) and its preprocessing amortised over the target's frames.
void write_pick(JsonWriter& json, const std::string& key, const Pick& p, const RecommendationTarget& target) {
  json.begin_object(key).value("technique", to_string(p.technique)).value("layers", to_string(p.layers));
  json.value("label", p.label());
  write_spread(json, "ns_per_ray", p.time(), 1e9);
  const Spread t = p.time();
  json.begin_object("rays_per_second")
      .value("median", 1.0 / t.median)
      .value("min", 1.0 / t.max)
      .value("max", 1.0 / t.min)
      .end_object();
  json.begin_array("rows");
  for (const Candidate& r : p.rows) {
    json.begin_object().value("id", r.id).value("heightfield", r.heightfield);
    json.value(measure_name(target.percentile), r.error(target.percentile))
        .value("wrong_surface_rate", r.wrong_surface_rate);
    json.value("samples_per_ray", r.samples_per_ray).value("rays", r.rays);
    write_spread(json, "ms_per_frame", spread_of(r.seconds), 1e3);
    if (r.precompute_seconds)
      json.value("precompute_seconds", *r.precompute_seconds)
          .value("precompute_ms_per_frame", *r.precompute_seconds * 1e3 / double(target.frames));
    else
      json.null("precompute_seconds").null("precompute_ms_per_frame");
    json.end_object();
  }
  json.end_array().end_object();
}

void write_answer(JsonWriter& json, const std::string& key, const Answer& a,
                  const RecommendationTarget& target) {
  json.begin_object(key);
  a.heightfield.empty() ? json.null("heightfield") : json.value("heightfield", a.heightfield);
  json.value("settings", a.settings).value("meeting", a.meeting);
  a.choice ? write_pick(json, "choice", *a.choice, target) : (void)json.null("choice");
  a.runner_up ? write_pick(json, "runner_up", *a.runner_up, target) : (void)json.null("runner_up");
  a.runner_up_ratio ? write_spread(json, "runner_up_time_ratio", *a.runner_up_ratio)
                    : (void)json.null("runner_up_time_ratio");
  a.closest ? write_pick(json, "closest", *a.closest, target) : (void)json.null("closest");
  json.end_object();
}

// "cone 32: 12.5 (11.7-13) ns/ray, p99 0.429 texel, wrong surface 0.375%, preprocessing 0.5 s (0.139 ms a
// frame over 3600 frames)"
std::string pick_line(const Pick& p, const RecommendationTarget& t) {
  const Spread time = p.time();
  std::string line =
      p.label() + ": " +
      string_format("%.3g (%.3g-%.3g) ns/ray", time.median * 1e9, time.min * 1e9, time.max * 1e9);
  double worst_error = 0, worst_wrong = 0, precompute = 0;
  for (const Candidate& r : p.rows) {
    worst_error = std::max(worst_error, r.error(t.percentile));
    worst_wrong = std::max(worst_wrong, r.wrong_surface_rate);
    precompute = std::max(precompute, r.precompute_seconds.value_or(0.0));
  }
  line += ", " + to_string(t.percentile) +
          string_format(" %.3g texel, wrong surface %.3g%%", worst_error, 100 * worst_wrong) +
          (p.rows.size() > 1 ? " (worst heightfield)" : "");
  if (precompute > 0)
    line += string_format(", preprocessing %.3g s (%.3g ms a frame over %d frames)", precompute,
                          precompute * 1e3 / t.frames, t.frames);
  return line;
}

std::string answer_line(const Answer& a, const RecommendationTarget& t) {
  if (!a.choice) {
    std::string line = "none of " + std::to_string(a.settings) + " meets the target";
    return a.closest ? line + "; the nearest: " + pick_line(*a.closest, t) : line;
  }
  std::string line = pick_line(*a.choice, t);
  if (a.runner_up && a.runner_up_ratio) {
    const Spread& r = *a.runner_up_ratio;
    line += "; next fastest " + a.runner_up->label() +
            string_format(": %.2fx (%.2f-%.2f) the time", r.median, r.min, r.max) +
            (r.min <= 1.0 && r.max >= 1.0 ? " (not distinguishable)" : "");
  }
  return line;
}

}  // namespace

std::string recommendation_json(const Recommendation& r) {
  JsonWriter json;
  json.begin_object()
      .value("format", "heightmarch-recommendation")
      .value("format_version", kRecommendationFormatVersion);
  json.begin_object("target")
      .value("measure", measure_name(r.target.percentile))
      .value("uv_error_texels", r.target.uv_error_texels)
      .value("wrong_surface_rate", r.target.wrong_surface_rate)
      .value("frames", r.target.frames)
      .value("description", describe(r.target))
      .end_object();
  json.begin_array("backends");
  for (const BackendRecommendation& b : r.backends) {
    json.begin_object()
        .value("backend", b.backend.backend())
        .value("threads", b.backend.threads)
        .value("name", b.backend.name());
    write_answer(json, "all_heightfields", b.all_heightfields, r.target);
    json.begin_array("per_heightfield");
    for (const Answer& a : b.per_heightfield) write_answer(json, "", a, r.target);
    json.end_array().end_object();
  }
  json.end_array().end_object();
  return json.str() + "\n";
}

std::string recommendation_markdown(const Recommendation& r) {
  std::string md = "At " + describe(r.target) +
                   ", the fastest configuration by time per ray (median (min-max) over "
                   "the repetitions) on each heightfield, and one setting for all of them:\n\n"
                   "| backend | heightfield | recommendation |\n|---|---|---|\n";
  for (const BackendRecommendation& b : r.backends) {
    md += "| " + markdown_text(b.backend.name()) + " | **all** | " +
          markdown_text(answer_line(b.all_heightfields, r.target)) + " |\n";
    for (const Answer& a : b.per_heightfield)
      md += "| " + markdown_text(b.backend.name()) + " | " + markdown_text(a.heightfield) + " | " +
            markdown_text(answer_line(a, r.target)) + " |\n";
  }
  return md;
}

std::string recommendation_text(const Recommendation& r) {
  std::string text = "Recommendation at " + describe(r.target) + ", fastest by time per ray:\n";
  for (const BackendRecommendation& b : r.backends) {
    text +=
        "  " + b.backend.name() + ", every heightfield: " + answer_line(b.all_heightfields, r.target) + "\n";
    for (const Answer& a : b.per_heightfield)
      text += "    " + printable(a.heightfield) + ": " + answer_line(a, r.target) + "\n";
  }
  return text;
}

}  // namespace heightmarch
