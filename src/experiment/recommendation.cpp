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
  return (gl.empty() ? backend() : gl) + ", " + std::to_string(threads) +
         (threads == 1 ? " thread" : " threads");
}

Accuracy accuracy_of(const ErrorSummary& e) {
  Accuracy a;
  const double values[] = {e.p50, e.p95, e.p99, e.max};
  const Interval intervals[] = {e.p50_ci, e.p95_ci, e.p99_ci, {e.max, e.max}};
  for (ErrorPercentile p : kErrorPercentiles) {
    a.uv_error[int(p)] = values[int(p)];
    a.uv_error_ci[int(p)] = intervals[int(p)];
  }
  a.wrong_surface_rate = e.wrong_surface_rate;
  a.wrong_surface_ci = e.wrong_surface_ci;
  a.rays = e.rays;
  return a;
}

std::vector<Candidate> candidates(const std::vector<Measurement>& rows) {
  std::vector<Candidate> out;
  for (const Measurement& m : rows) {
    const Configuration& c = m.config;
    const ViewSpec::Kind kind = c.view.kind;
    if (!(c.purposes & (kPurposeMatrix | kPurposeClaims | kPurposeGlsl)) ||
        !(c.kind == RunKind::trace || c.kind == RunKind::glsl) || !c.has_technique() || !m.errors ||
        m.seconds.empty() || !m.failure.empty() || kind == ViewSpec::Kind::sweep ||
        kind == ViewSpec::Kind::rays_file || c.view.fresh_rays > 0 || m.rays == 0)
      continue;
    Candidate k;
    k.id = m.id;
    k.heightfield = c.heightfield.label();
    k.depth_map_width = m.depth_map_width;
    k.depth_map_height = m.depth_map_height;
    k.backend = {c.kind, c.kind == RunKind::trace ? c.isa : Isa::scalar, c.threads,
                 m.gl ? m.gl->label() : ""};
    k.grid = c.purposes & (kPurposeMatrix | kPurposeClaims);
    k.technique = c.params.technique;
    k.layers = c.params.layers;
    k.filter = c.params.filter;
    k.selection = accuracy_of(*m.errors);
    Configuration twin = c;
    twin.view = held_out_view(c.view);
    for (const Measurement& h : rows)
      if ((h.config.purposes & kPurposeHeldOut) && h.config.same_measurement(twin) && h.errors &&
          h.failure.empty()) {
        k.held_out = accuracy_of(*h.errors);
        k.held_out_id = h.id;
      }
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

bool meets(const Accuracy& a, const RecommendationTarget& t) {
  return a.error(t.percentile) <= t.uv_error_texels && a.wrong_surface_rate <= t.wrong_surface_rate;
}

// A measure over its bound (1: on it).
double over(double value, double bound) { return bound > 0 ? value / bound : (value > 0 ? HUGE_VAL : 0.0); }

// How far a row is from the target: the larger of its two measures over their bounds, on its
// window's figures and its held-out ones alike (1: on it); and which measure that is.
std::pair<double, std::string> shortfall(const Candidate& c, const RecommendationTarget& t) {
  std::pair<double, std::string> worst{0.0, ""};
  for (const Accuracy* a : {&c.selection, c.held_out ? &*c.held_out : nullptr}) {
    if (!a) continue;
    worst = std::max(worst, {over(a->error(t.percentile), t.uv_error_texels), to_string(t.percentile)});
    worst =
        std::max(worst, {over(a->wrong_surface_rate, t.wrong_surface_rate), std::string("wrong surface")});
  }
  return worst;
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

TimeRatio time_ratio(const Pick& slower, const Pick& faster) {
  TimeRatio r;
  r.ratio = slower.time().median / faster.time().median;
  std::vector<double> ratios;
  for (std::size_t i = 0; i < std::min(slower.seconds_per_ray.size(), faster.seconds_per_ray.size()); ++i)
    ratios.push_back(slower.seconds_per_ray[i] / faster.seconds_per_ray[i]);
  r.per_round = spread_of(ratios);
  return r;
}

// settings: each a setting's rows on the heightfields asked for (one row each). Ranked by median
// time; the choice is the fastest that meets the target on the window and on the held-out set.
Answer answer(const std::string& heightfield, const std::vector<std::vector<Candidate>>& settings,
              const RecommendationTarget& target) {
  Answer a;
  a.heightfield = heightfield;
  a.settings = int(settings.size());
  a.held_out_checked = !settings.empty();
  std::vector<Pick> picks;
  for (const std::vector<Candidate>& rows : settings) {
    picks.push_back(make_pick(rows));
    for (const Candidate& r : rows) a.held_out_checked = a.held_out_checked && r.held_out;
  }
  std::stable_sort(picks.begin(), picks.end(),
                   [](const Pick& x, const Pick& y) { return x.time().median < y.time().median; });
  const auto all_meet = [&](const Pick& p, bool held_out) {
    return std::all_of(p.rows.begin(), p.rows.end(), [&](const Candidate& r) {
      return held_out ? !r.held_out || meets(*r.held_out, target) : meets(r.selection, target);
    });
  };
  const auto worst = [&](const Pick& p) {
    std::pair<double, std::string> w{0.0, ""};
    for (const Candidate& r : p.rows) w = std::max(w, shortfall(r, target));
    return w;
  };
  double closest_shortfall = HUGE_VAL;
  for (const Pick& p : picks) {
    const bool on_window = all_meet(p, false), on_held_out = all_meet(p, true);
    if (on_window && on_held_out) {
      ++a.meeting;
      if (!a.choice) {
        a.choice = p;
      } else if (!a.runner_up) {
        a.runner_up = p;
        a.runner_up_ratio = time_ratio(p, *a.choice);
      }
      continue;
    }
    if (a.choice) continue;
    if (on_window) a.failed_held_out.push_back(p);
    const auto [margin, measure] = worst(p);
    if (!a.near_miss && margin < 1.0 + kNearMissShare) a.near_miss = NearMiss{p, margin, measure};
    if (margin < closest_shortfall) a.closest = p, closest_shortfall = margin;
  }
  if (a.choice) a.closest.reset();
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
  if (!all.empty()) out.filter = all.front().filter;
  for (const Candidate& c : all)
    if (c.filter != out.filter)
      throw InputError("candidates read with both filters: a recommendation is made under one (rows " +
                       std::to_string(all.front().id) + " and " + std::to_string(c.id) + ")");
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

void write_interval(JsonWriter& json, const std::string& key, const Interval& i) {
  json.begin_array(key).value("", i.low).value("", i.high).end_array();
}

// A row's figures on one view set: the target's percentile and the wrong-surface rate, each with
// its 95% interval.
void write_accuracy(JsonWriter& json, const std::string& key, const Accuracy& a,
                    const RecommendationTarget& t) {
  json.begin_object(key).value(measure_name(t.percentile), a.error(t.percentile));
  write_interval(json, measure_name(t.percentile) + "_ci", a.error_ci(t.percentile));
  json.value("wrong_surface_rate", a.wrong_surface_rate);
  write_interval(json, "wrong_surface_ci", a.wrong_surface_ci);
  json.value("rays", a.rays).value("meets", meets(a, t)).end_object();
}

// A pick: its setting, its time, and per heightfield the row with its measures (on the window,
// and on the held-out set where measured), the time of one frame (one trace of the window) and
// its preprocessing amortised over the target's frames.
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
    json.value(measure_name(target.percentile), r.selection.error(target.percentile))
        .value("wrong_surface_rate", r.selection.wrong_surface_rate);
    write_accuracy(json, "selection", r.selection, target);
    if (r.held_out) {
      json.value("held_out_id", r.held_out_id);
      write_accuracy(json, "held_out", *r.held_out, target);
    } else {
      json.null("held_out_id").null("held_out");
    }
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
  json.value("settings", a.settings)
      .value("meeting", a.meeting)
      .value("held_out_checked", a.held_out_checked);
  a.choice ? write_pick(json, "choice", *a.choice, target) : (void)json.null("choice");
  a.runner_up ? write_pick(json, "runner_up", *a.runner_up, target) : (void)json.null("runner_up");
  if (a.runner_up_ratio) {
    json.begin_object("runner_up_time_ratio").value("ratio", a.runner_up_ratio->ratio);
    write_spread(json, "per_round", a.runner_up_ratio->per_round);
    json.value("distinguishable", a.runner_up_ratio->distinguishable()).end_object();
  } else {
    json.null("runner_up_time_ratio");
  }
  json.begin_array("failed_held_out");
  for (const Pick& p : a.failed_held_out) write_pick(json, "", p, target);
  json.end_array();
  if (a.near_miss) {
    json.begin_object("near_miss")
        .value("margin", a.near_miss->margin)
        .value("measure", a.near_miss->measure);
    write_pick(json, "setting", a.near_miss->pick, target);
    json.end_object();
  } else {
    json.null("near_miss");
  }
  a.closest ? write_pick(json, "closest", *a.closest, target) : (void)json.null("closest");
  json.end_object();
}

// "p99 0.429 (0.41-0.45) texel, wrong surface 0.375% (0.33-0.42%)": a setting's worst rows on one
// view set (each measure at its worst heightfield).
std::string figures_text(const Pick& p, const RecommendationTarget& t, bool held_out) {
  const Accuracy* worst_error = nullptr;
  const Accuracy* worst_wrong = nullptr;
  for (const Candidate& r : p.rows) {
    const Accuracy* a = held_out ? (r.held_out ? &*r.held_out : nullptr) : &r.selection;
    if (!a) return "not measured";
    if (!worst_error || a->error(t.percentile) > worst_error->error(t.percentile)) worst_error = a;
    if (!worst_wrong || a->wrong_surface_rate > worst_wrong->wrong_surface_rate) worst_wrong = a;
  }
  const Interval e = worst_error->error_ci(t.percentile), w = worst_wrong->wrong_surface_ci;
  return to_string(t.percentile) +
         string_format(" %.3g (%.3g-%.3g) texel, wrong surface %.3g%% (%.3g-%.3g%%)",
                       worst_error->error(t.percentile), e.low, e.high, 100 * worst_wrong->wrong_surface_rate,
                       100 * w.low, 100 * w.high);
}

// "cone 32: 12.5 (11.7-13) ns/ray; held-out p99 0.43 (0.41-0.45) texel, wrong surface 0.38%
// (0.33-0.42%); window p99 ...; preprocessing 0.5 s (0.139 ms a frame over 3600 frames)"
std::string pick_line(const Pick& p, const RecommendationTarget& t) {
  const Spread time = p.time();
  std::string line =
      p.label() + ": " +
      string_format("%.3g (%.3g-%.3g) ns/ray", time.median * 1e9, time.min * 1e9, time.max * 1e9);
  const bool held_out =
      std::all_of(p.rows.begin(), p.rows.end(), [](const Candidate& r) { return r.held_out; });
  if (held_out) line += "; held-out " + figures_text(p, t, true);
  line += "; " + std::string(held_out ? "window " : "") + figures_text(p, t, false) +
          (p.rows.size() > 1 ? " (worst heightfield)" : "");
  double precompute = 0;
  for (const Candidate& r : p.rows) precompute = std::max(precompute, r.precompute_seconds.value_or(0.0));
  if (precompute > 0)
    line += string_format("; preprocessing %.3g s (%.3g ms a frame over %d frames)", precompute,
                          precompute * 1e3 / t.frames, t.frames);
  return line;
}

std::string answer_line(const Answer& a, const RecommendationTarget& t) {
  std::string line;
  if (!a.failed_held_out.empty()) {
    line += "not ";
    for (std::size_t i = 0; i < a.failed_held_out.size(); ++i)
      line += (i ? ", " : "") + a.failed_held_out[i].label();
    line += std::string(a.failed_held_out.size() > 1 ? ", which meet" : ", which meets") +
            " the target on the window but not on the held-out views (" +
            figures_text(a.failed_held_out.front(), t, true) + "); ";
    line += a.choice ? "the next that holds: " : "";
  }
  if (!a.choice) {
    line += "none of " + std::to_string(a.settings) + " meets the target";
    if (a.closest) line += "; the nearest: " + pick_line(*a.closest, t);
  } else {
    line += pick_line(*a.choice, t);
    if (a.runner_up && a.runner_up_ratio) {
      const TimeRatio& r = *a.runner_up_ratio;
      line +=
          "; next fastest " + a.runner_up->label() +
          string_format(": %.2fx the time (per round %.2f-%.2f)", r.ratio, r.per_round.min, r.per_round.max) +
          (r.distinguishable() ? "" : ", not distinguishable");
    }
  }
  if (a.near_miss && (!a.closest || a.near_miss->pick.label() != a.closest->label()))
    line += "; near miss " + a.near_miss->pick.label() +
            string_format(": %.2fx faster, %s %.0f%% over its bound",
                          a.choice ? a.choice->time().median / a.near_miss->pick.time().median : 1.0,
                          a.near_miss->measure.c_str(), 100 * (a.near_miss->margin - 1));
  if (!a.held_out_checked) line += " (not checked on held-out views)";
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
  json.value("filter", to_string(r.filter));
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
  std::string md = "At " + describe(r.target) + ", " + to_string(r.filter) +
                   " filtering, the fastest configuration by time per ray (median (min-max) over "
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
  std::string text = "Recommendation at " + describe(r.target) + ", " + to_string(r.filter) +
                     " filtering, fastest by time per ray:\n";
  for (const BackendRecommendation& b : r.backends) {
    text +=
        "  " + b.backend.name() + ", every heightfield: " + answer_line(b.all_heightfields, r.target) + "\n";
    for (const Answer& a : b.per_heightfield)
      text += "    " + printable(a.heightfield) + ": " + answer_line(a, r.target) + "\n";
  }
  return text;
}

}  // namespace heightmarch
