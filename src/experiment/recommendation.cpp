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

std::string to_string(ErrorUnit unit) { return unit == ErrorUnit::pixels ? "pixels" : "texels"; }

ErrorUnit parse_error_unit(const std::string& name) {
  if (name == "texels") return ErrorUnit::texels;
  if (name == "pixels") return ErrorUnit::pixels;
  throw InputError("unknown error unit '" + name + "' (texels or pixels)");
}

UnitDistributions distributions_in(ErrorUnit unit) {
  const bool pixels = unit == ErrorUnit::pixels;
  return {distribution_named(pixels ? "search_pixel_error" : "search_error"),
          distribution_named(pixels ? "filter_pixel_bias" : "filter_bias"),
          distribution_named(pixels ? "pixel_error" : "uv_error")};
}

std::string measure_name(const RecommendationTarget& t) {
  return distributions_in(t.unit).search.measure(to_string(t.percentile));
}

void validate(const RecommendationTarget& t) {
  if (!(std::isfinite(t.max_error) && t.max_error >= 0))
    throw InputError("the target's error bound must be a number of " + to_string(t.unit) + " >= 0");
  if (!(std::isfinite(t.max_wrong_rate) && t.max_wrong_rate >= 0 && t.max_wrong_rate <= 1))
    throw InputError("the target's wrong-" + std::string(t.unit == ErrorUnit::pixels ? "pixel" : "surface") +
                     " bound must be a share in [0, 1] (a percentage in [0, 100])");
  if (t.frames < 1) throw InputError("the frames preprocessing is amortised over must be at least 1");
}

namespace {

// "pixel", "texel"; "wrong pixel", "wrong surface"
std::string unit_word(ErrorUnit unit) { return unit == ErrorUnit::pixels ? "pixel" : "texel"; }
std::string wrong_words(ErrorUnit unit) {
  return unit == ErrorUnit::pixels ? "wrong pixel" : "wrong surface";
}

}  // namespace

std::string describe(const RecommendationTarget& t) {
  return string_format("%s <= %g %s, %s <= %g%%", to_string(t.percentile).c_str(), t.max_error,
                       unit_word(t.unit).c_str(), wrong_words(t.unit).c_str(), 100.0 * t.max_wrong_rate);
}

std::string RecommendationBackend::backend() const { return kind == RunKind::glsl ? "glsl" : to_string(isa); }

std::string RecommendationBackend::name() const {
  return (gl.empty() ? backend() : gl) + ", " + std::to_string(threads) +
         (threads == 1 ? " thread, " : " threads, ") + to_string(filter);
}

Figures figures_of(const ErrorDistribution& d) {
  Figures f;
  const double values[] = {d.p50, d.p95, d.p99, d.max};
  const Interval intervals[] = {d.p50_ci, d.p95_ci, d.p99_ci, {d.max, d.max}};
  for (ErrorPercentile p : kErrorPercentiles) {
    f.values[int(p)] = values[int(p)];
    f.intervals[int(p)] = intervals[int(p)];
  }
  f.wrong_rate = d.wrong_rate;
  f.wrong_ci = d.wrong_ci;
  return f;
}

Accuracy accuracy_of(const ErrorSummary& e, ErrorUnit unit) {
  const UnitDistributions d = distributions_in(unit);
  const ErrorDistribution& search = e.*d.search.member;
  if (!search.measured && e.rays > 0)
    throw InputError("no errors in " + to_string(unit) + ": the rays have no pixel grid (a rays file)");
  Accuracy a;
  a.search = figures_of(search);
  a.bias = figures_of(e.*d.bias.member);
  a.total = figures_of(e.*d.total.member);
  a.rays = e.rays;
  return a;
}

bool meets(const Accuracy& a, const RecommendationTarget& t) {
  return a.error(t.percentile) <= t.max_error && a.wrong_rate() <= t.max_wrong_rate;
}

bool filter_dominated(const Accuracy& a, const RecommendationTarget& t) {
  const bool bias_misses = a.bias.error(t.percentile) > t.max_error || a.bias.wrong_rate > t.max_wrong_rate;
  return bias_misses && a.bias.error(t.percentile) >= a.search.error(t.percentile);
}

std::vector<Candidate> candidates(const std::vector<Measurement>& rows, ErrorUnit unit) {
  std::vector<Candidate> out;
  for (const Measurement& m : rows) {
    const Configuration& c = m.config;
    const ViewSpec::Kind kind = c.view.kind;
    if (!(c.purposes & (kPurposeMatrix | kPurposeFilters | kPurposeClaims | kPurposeGlsl)) ||
        !(c.kind == RunKind::trace || c.kind == RunKind::glsl) || !c.has_technique() || !m.errors ||
        m.seconds.empty() || !m.failure.empty() || kind == ViewSpec::Kind::sweep ||
        kind == ViewSpec::Kind::rays_file || c.view.fresh_rays > 0 || m.rays == 0)
      continue;
    Candidate k;
    k.id = m.id;
    k.heightfield = c.heightfield.label();
    k.depth_map_width = m.depth_map_width;
    k.depth_map_height = m.depth_map_height;
    k.backend = {c.kind, c.kind == RunKind::trace ? c.isa : Isa::scalar, c.threads, m.gl ? m.gl->label() : "",
                 c.params.filter};
    k.grid = c.purposes & (kPurposeMatrix | kPurposeFilters | kPurposeClaims);
    k.technique = c.params.technique;
    k.layers = c.params.layers;
    k.filter = c.params.filter;
    k.selection = accuracy_of(*m.errors, unit);
    Configuration twin = c;
    twin.view = held_out_view(c.view);
    for (const Measurement& h : rows)
      if ((h.config.purposes & kPurposeHeldOut) && h.config.same_measurement(twin) && h.errors &&
          h.failure.empty()) {
        k.held_out = accuracy_of(*h.errors, unit);
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

// A measure over its bound (1: on it).
double over(double value, double bound) { return bound > 0 ? value / bound : (value > 0 ? HUGE_VAL : 0.0); }

// How far a row is from the target: the larger of its two measures over their bounds, on its
// window's figures and its held-out ones alike (1: on it); and which measure that is.
std::pair<double, std::string> shortfall(const Candidate& c, const RecommendationTarget& t) {
  std::pair<double, std::string> worst{0.0, ""};
  for (const Accuracy* a : {&c.selection, c.held_out ? &*c.held_out : nullptr}) {
    if (!a) continue;
    worst = std::max(worst, {over(a->error(t.percentile), t.max_error), to_string(t.percentile)});
    worst = std::max(worst, {over(a->wrong_rate(), t.max_wrong_rate), wrong_words(t.unit)});
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
  if (const std::optional<Pick>& shown = a.choice ? a.choice : a.closest)
    a.filter_dominated = std::any_of(shown->rows.begin(), shown->rows.end(), [&](const Candidate& r) {
      return r.filter == Filter::trilinear && filter_dominated(r.selection, target);
    });
  return a;
}

bool same_setting(const Candidate& a, const Candidate& b) {
  return a.technique == b.technique && a.layers == b.layers;
}

// The declared backends: the grid's CPU backends (one per filter), then GLSL at each of their thread
// counts and filters.
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
      if (c.backend.kind == RunKind::glsl && c.backend.threads == out[i].threads &&
          c.backend.filter == out[i].filter)
        add(c.backend);
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

void write_interval(JsonWriter& json, const std::string& key, const Interval& i) {
  json.begin_array(key).value("", i.low).value("", i.high).end_array();
}

// A row's figures on one view set: the target's percentile of its search error and its wrong rate,
// each with its 95% interval, whether they meet the target; and the same percentile and wrong
// rate of the filter's bias and of the error against level 0, under their own names.
void write_accuracy(JsonWriter& json, const std::string& key, const Accuracy& a,
                    const RecommendationTarget& t) {
  const UnitDistributions d = distributions_in(t.unit);
  const std::string p = to_string(t.percentile);
  json.begin_object(key).value(d.search.measure(p), a.error(t.percentile));
  write_interval(json, d.search.measure(p) + "_ci", a.error_ci(t.percentile));
  json.value(d.search.wrong_name, a.wrong_rate());
  write_interval(json, d.search.wrong_ci_name(), a.search.wrong_ci);
  for (const auto& [info, figures] : {std::pair{&d.bias, &a.bias}, std::pair{&d.total, &a.total}})
    json.value(info->measure(p), figures->error(t.percentile)).value(info->wrong_name, figures->wrong_rate);
  json.value("rays", a.rays).value("meets", meets(a, t)).value("filter_dominated", filter_dominated(a, t));
  json.end_object();
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
    json.value(measure_name(target), r.selection.error(target.percentile))
        .value(distributions_in(target.unit).search.wrong_name, r.selection.wrong_rate());
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
  json.value("filter_dominated", a.filter_dominated).end_object();
}

// "p99 0.429 (0.41-0.45) pixel, wrong pixel 0.375% (0.33-0.42%)": a setting's worst rows on one
// view set (each measure at its worst heightfield); under trilinear with the filter's bias beside
// it ("; filter bias p99 2.1 pixel, wrong pixel 4.2%").
std::string figures_text(const Pick& p, const RecommendationTarget& t, bool held_out) {
  const Accuracy* worst_error = nullptr;
  const Accuracy* worst_wrong = nullptr;
  const Accuracy* worst_bias = nullptr;
  for (const Candidate& r : p.rows) {
    const Accuracy* a = held_out ? (r.held_out ? &*r.held_out : nullptr) : &r.selection;
    if (!a) return "not measured";
    if (!worst_error || a->error(t.percentile) > worst_error->error(t.percentile)) worst_error = a;
    if (!worst_wrong || a->wrong_rate() > worst_wrong->wrong_rate()) worst_wrong = a;
    if (r.filter == Filter::trilinear &&
        (!worst_bias || a->bias.error(t.percentile) > worst_bias->bias.error(t.percentile)))
      worst_bias = a;
  }
  const Interval e = worst_error->error_ci(t.percentile), w = worst_wrong->search.wrong_ci;
  const std::string unit = unit_word(t.unit), wrong = wrong_words(t.unit);
  std::string text = to_string(t.percentile) +
                     string_format(" %.3g (%.3g-%.3g) %s, %s %.3g%% (%.3g-%.3g%%)",
                                   worst_error->error(t.percentile), e.low, e.high, unit.c_str(),
                                   wrong.c_str(), 100 * worst_wrong->wrong_rate(), 100 * w.low, 100 * w.high);
  if (worst_bias)
    text += string_format("; filter bias %s %.3g %s, %s %.3g%%", to_string(t.percentile).c_str(),
                          worst_bias->bias.error(t.percentile), unit.c_str(), wrong.c_str(),
                          100 * worst_bias->bias.wrong_rate);
  return text;
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
  if (a.filter_dominated) line += "; filter-dominated: more layers do not change what a player sees here";
  return line;
}

}  // namespace

std::string recommendation_json(const Recommendation& r) {
  JsonWriter json;
  json.begin_object()
      .value("format", "heightmarch-recommendation")
      .value("format_version", kRecommendationFormatVersion);
  const UnitDistributions d = distributions_in(r.target.unit);
  json.begin_object("target")
      .value("measure", measure_name(r.target))
      .value("wrong_measure", d.search.wrong_name)
      .value("bias_measure", d.bias.measure(to_string(r.target.percentile)))
      .value("bias_wrong_measure", d.bias.wrong_name)
      .value("total_measure", d.total.measure(to_string(r.target.percentile)))
      .value("total_wrong_measure", d.total.wrong_name)
      .value("unit", to_string(r.target.unit))
      .value("max_error", r.target.max_error)
      .value("max_wrong_rate", r.target.max_wrong_rate)
      .value("frames", r.target.frames)
      .value("description", describe(r.target))
      .end_object();
  json.begin_array("backends");
  for (const BackendRecommendation& b : r.backends) {
    json.begin_object()
        .value("backend", b.backend.backend())
        .value("threads", b.backend.threads)
        .value("filter", to_string(b.backend.filter))
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
  std::string md =
      "At " + describe(r.target) +
      " (the search error, against the surface each ray reads), the fastest configuration by time "
      "per ray (median (min-max) over the repetitions) at each backend and filter, on each "
      "heightfield, and one setting for all of them:\n\n"
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
  std::string text = "Recommendation at " + describe(r.target) +
                     " (the search error, against the surface each ray reads), fastest by time per ray:\n";
  for (const BackendRecommendation& b : r.backends) {
    text +=
        "  " + b.backend.name() + ", every heightfield: " + answer_line(b.all_heightfields, r.target) + "\n";
    for (const Answer& a : b.per_heightfield)
      text += "    " + printable(a.heightfield) + ": " + answer_line(a, r.target) + "\n";
  }
  return text;
}

}  // namespace heightmarch
