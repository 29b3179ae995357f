#include "claims/claims.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "io/json_writer.hpp"
#include "io/markdown.hpp"
#include "util/string_format.hpp"

namespace heightmarch {

const ClaimFigure* ClaimsData::find(const std::string& heightfield, const ClaimRow& row) const {
  for (const ClaimFigure& f : figures)
    if (f.heightfield == heightfield && f.row == row) return &f;
  return nullptr;
}

std::vector<std::string> ClaimsData::heightfields(bool large_maps) const {
  std::vector<std::string> names;
  for (const ClaimFigure& f : figures)
    if ((f.row.view == ClaimView::large_map) == large_maps &&
        std::find(names.begin(), names.end(), f.heightfield) == names.end())
      names.push_back(f.heightfield);
  return names;
}

std::string to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::holds:
      return "holds";
    case Verdict::mostly_holds:
      return "mostly holds";
    case Verdict::holds_partly:
      return "holds partly";
    case Verdict::mostly_refuted:
      return "mostly refuted";
    case Verdict::refuted:
      return "refuted";
    case Verdict::not_measured:
      return "not measured";
  }
  return "?";
}

Verdict verdict_of(std::size_t passed, std::size_t checks) {
  if (checks == 0) return Verdict::not_measured;
  if (passed == checks) return Verdict::holds;
  if (passed == 0) return Verdict::refuted;
  const double share = double(passed) / double(checks);
  if (share >= kMostlyShare) return Verdict::mostly_holds;
  if (share <= 1.0 - kMostlyShare) return Verdict::mostly_refuted;
  return Verdict::holds_partly;
}

std::string ClaimCheck::where() const { return at.empty() ? heightfield : heightfield + ", " + at; }

std::string describe(const ClaimRow& row) {
  std::string text = to_string(row.technique) + " " + to_string(row.layers);
  if (row.view == ClaimView::sweep) text += " at " + std::to_string(int(row.theta)) + " deg";
  if (row.view == ClaimView::large_map) text += " on the large map";
  return text;
}

namespace {

// A speed as median (min-max) Mrays/s over the timed repetitions, or "not timed".
std::string speed(const ClaimFigure& f) {
  if (f.rays_per_second <= 0) return "not timed";
  return string_format("%.1f (%.1f-%.1f) Mrays/s", f.rays_per_second / 1e6, f.rays_per_second_min / 1e6,
                       f.rays_per_second_max / 1e6);
}

}  // namespace

std::string compare_speeds(const ClaimFigure& a, const ClaimFigure& b) {
  if (a.rays_per_second <= 0 || b.rays_per_second <= 0) return "not timed";
  if (a.rays_per_second_min > b.rays_per_second_max) return "faster";
  if (a.rays_per_second_max < b.rays_per_second_min) return "slower";
  return "not distinguishable (spreads overlap)";
}

namespace {

using T = Technique;

// The layer specs the rules name: fixed counts (N: one sample for the one-sample techniques) and
// the tutorial's dynamic range.
constexpr LayerSpec kDynamic = LayerSpec::range(8, 32);
std::vector<LayerSpec> fixed(std::initializer_list<int> counts) {
  std::vector<LayerSpec> out;
  for (int n : counts) out.push_back(LayerSpec::fixed(n));
  return out;
}

// "0.54x, against at most 0.5x": the ratio a rule decides on, against its bound.
std::string ratio_text(double value, double reference, const char* bound) {
  return reference > 0 ? string_format("%.3gx, against %s", value / reference, bound)
                       : std::string("no reference");
}

// Where a claim fails (or, mostly refuted, where it holds), its checks grouped by place: "at 8
// layers on bricks (0.54x, against at most 0.5x) and toybox (0.52x, ...); on spikes (...)". At
// most kShownPlaces places, then how many more.
std::string where_text(const std::vector<ClaimCheck>& checks, bool passed) {
  constexpr std::size_t kShownPlaces = 6;
  std::vector<std::pair<std::string, std::vector<const ClaimCheck*>>> places;
  for (const ClaimCheck& c : checks) {
    if (c.passed != passed) continue;
    auto it = std::find_if(places.begin(), places.end(), [&](const auto& p) { return p.first == c.at; });
    if (it == places.end()) it = places.insert(places.end(), {c.at, {}});
    it->second.push_back(&c);
  }
  std::string text;
  for (std::size_t i = 0; i < places.size() && i < kShownPlaces; ++i) {
    const auto& [at, list] = places[i];
    text += (i ? "; " : "") + (at.empty() ? std::string("on ") : "at " + at + " on ");
    for (std::size_t k = 0; k < list.size(); ++k)
      text += (k == 0                 ? ""
               : k + 1 == list.size() ? " and "
                                      : ", ") +
              list[k]->heightfield + (list[k]->deciding.empty() ? "" : " (" + list[k]->deciding + ")");
  }
  if (places.size() > kShownPlaces)
    text += string_format("; and at %zu more places", places.size() - kShownPlaces);
  return text;
}

// "holds on 13 of 15 checks; fails at 8 layers on ...", "mostly refuted: holds on 4 of 20 checks,
// only at 16 layers on ...".
std::string summary_of(const ClaimResult& r) {
  const std::size_t n = r.checks.size();
  if (n == 0) return "not measured";
  const std::string count = string_format("%zu of %zu checks", r.passed, n);
  switch (r.verdict) {
    case Verdict::holds:
      return "holds on all " + std::to_string(n) + " checks";
    case Verdict::refuted:
      return "refuted on all " + std::to_string(n) + " checks";
    case Verdict::mostly_refuted:
      return "mostly refuted: holds on " + count + ", only " + where_text(r.checks, true);
    default:
      return to_string(r.verdict) + ": holds on " + count + "; fails " + where_text(r.checks, false);
  }
}

// The rows as the rules name them: a technique at a layer spec (or a fixed count) on the default
// view, a sweep view at theta, or the large map.
ClaimRow at(Technique t, LayerSpec layers) { return {t, layers_for(t, layers), ClaimView::default_view, 0}; }
ClaimRow at(Technique t, int layers) { return at(t, LayerSpec::fixed(layers)); }
ClaimRow swept(Technique t, LayerSpec layers, double theta) {
  return {t, layers_for(t, layers), ClaimView::sweep, theta};
}
ClaimRow swept(Technique t, int layers, double theta) { return swept(t, LayerSpec::fixed(layers), theta); }
ClaimRow on_large_map(Technique t, int layers) {
  return {t, layers_for(t, LayerSpec::fixed(layers)), ClaimView::large_map, 0};
}

// Every technique at every layer spec (at every angle, on sweeps): a claim's declared rows.
std::vector<ClaimRow> rows(std::initializer_list<Technique> techniques, const std::vector<LayerSpec>& layers,
                           ClaimView view = ClaimView::default_view,
                           std::initializer_list<double> thetas = {0.0}) {
  std::vector<ClaimRow> out;
  for (Technique t : techniques)
    for (const LayerSpec& l : layers)
      for (double theta : thetas)
        out.push_back(view == ClaimView::sweep ? swept(t, l, theta) : ClaimRow{t, layers_for(t, l), view, 0});
  return out;
}
std::vector<ClaimRow> operator+(std::vector<ClaimRow> a, const std::vector<ClaimRow>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The lists the rules walk, declared once for rows and rules alike.
constexpr int kCurveLayers[] = {4, 8, 10, 16, 32, 64};     // a fixed-count curve
constexpr double kNearNormal[] = {0.0, 10.0, 20.0, 30.0};  // where the tutorial places 8-32's saving (C5)
constexpr int kLargeMapLayers[] = {64, 256, 1024};         // P2: up to about one layer per texel crossed

class ClaimBuilder {
 public:
  ClaimBuilder(const Claim& claim, const ClaimsData& data) : claim_(claim), data_(data) {
    result_.id = claim.id;
    result_.claim = claim.claim;
    result_.source = claim.source;
    result_.rule = claim.rule;
  }
  // A row's figure on a heightfield, or null where it was not measured. A rule reads only the
  // rows its claim declares: the plan measures nothing else.
  const ClaimFigure* get(const std::string& hf, const ClaimRow& row) const {
    if (std::find(claim_.rows.begin(), claim_.rows.end(), row) == claim_.rows.end())
      throw std::logic_error(claim_.id + " reads " + describe(row) + ", a row it does not declare");
    return data_.find(hf, row);
  }
  std::vector<std::string> heightfields(bool large_maps = false) const {
    return data_.heightfields(large_maps);
  }
  // A check on a heightfield, at a place on it ("32 layers"; empty: the field as a whole), with its
  // figures and the one that decides it against its bound.
  void check(const std::string& heightfield, std::string at, std::string figures, bool passed,
             std::string deciding) {
    result_.checks.push_back({heightfield, std::move(at), std::move(figures), passed, std::move(deciding)});
  }
  ClaimResult finish() {
    result_.passed = std::size_t(
        std::count_if(result_.checks.begin(), result_.checks.end(), [](auto& c) { return c.passed; }));
    result_.verdict = verdict_of(result_.passed, result_.checks.size());
    result_.summary = summary_of(result_);
    return result_;
  }

 private:
  const Claim& claim_;
  const ClaimsData& data_;
  ClaimResult result_;
};

// "Close" in quality (C5, C9): within the ratio, or within a quarter texel outright, since two
// errors far below a texel are alike on screen whatever their ratio.
bool close_in_quality(double error, double reference, double ratio) {
  return error <= ratio * reference || error - reference <= 0.25;
}

// Plain parallax's relative error: its uv error against the offset it has to find, |T - T*|.
double relative_error(const ClaimFigure& f) {
  return f.per_ray.offset_mean > 0 ? f.uv_error_mean / f.per_ray.offset_mean : 0.0;
}

ClaimResult claim_c1(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields()) {
    const ClaimFigure *a20 = c.get(hf, swept(T::parallax, 1, 20)),
                      *a30 = c.get(hf, swept(T::parallax, 1, 30));
    const ClaimFigure *a70 = c.get(hf, swept(T::parallax, 1, 70)),
                      *a80 = c.get(hf, swept(T::parallax, 1, 80));
    if (a20 && a30 && a70 && a80 && a20->per_ray.offset_mean > 0 && a30->per_ray.offset_mean > 0) {
      const double low = std::max(relative_error(*a20), relative_error(*a30));
      const double high = std::min(relative_error(*a70), relative_error(*a80));
      c.check(hf, "view angle",
              string_format(
                  "relative error %.3f at 70-80 deg vs %.3f at 20-30 deg (uv error %.3f and %.3f texels)",
                  high, low, std::min(a70->uv_error_mean, a80->uv_error_mean),
                  std::max(a20->uv_error_mean, a30->uv_error_mean)),
              high >= 2 * low, ratio_text(high, low, "at least 2x"));
    }
    if (const ClaimFigure* f = c.get(hf, at(T::parallax, 1)); f && f->per_ray.sharp_error_mean >= 0)
      c.check(
          hf, "sharp depth changes",
          string_format("error %.3f texels where |grad D| is in the top decile vs %.3f in the bottom half",
                        f->per_ray.sharp_error_mean, f->per_ray.smooth_error_mean),
          f->per_ray.sharp_error_mean >= 2 * f->per_ray.smooth_error_mean,
          ratio_text(f->per_ray.sharp_error_mean, f->per_ray.smooth_error_mean, "at least 2x"));
  }
  return c.finish();
}

ClaimResult claim_c2(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (double theta : {70.0, 80.0}) {
      const ClaimFigure *plain = c.get(hf, swept(T::parallax, 1, theta)),
                        *limited = c.get(hf, swept(T::parallax_limited, 1, theta));
      if (plain && limited)
        c.check(
            hf, string_format("%.0f deg", theta),
            string_format("limited %.3f vs plain %.3f texels", limited->uv_error_mean, plain->uv_error_mean),
            limited->uv_error_mean < plain->uv_error_mean,
            ratio_text(limited->uv_error_mean, plain->uv_error_mean, "below 1x"));
    }
  return c.finish();
}

ClaimResult claim_c3(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  const std::vector<int> counts = {4, 8, 16, 32, 64};
  for (const std::string& hf : c.heightfields())
    for (std::size_t i = 0; i + 1 < counts.size(); ++i) {
      const ClaimFigure *fewer = c.get(hf, at(T::steep, counts[i])),
                        *more = c.get(hf, at(T::steep, counts[i + 1]));
      if (fewer && more)
        c.check(hf, std::to_string(counts[i]) + " -> " + std::to_string(counts[i + 1]) + " layers",
                string_format("%.3f -> %.3f texels", fewer->uv_error_mean, more->uv_error_mean),
                more->uv_error_mean < fewer->uv_error_mean,
                ratio_text(more->uv_error_mean, fewer->uv_error_mean, "below 1x"));
    }
  return c.finish();
}

ClaimResult claim_c4(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields()) {
    const ClaimFigure *plain = c.get(hf, at(T::parallax, 1)), *steep = c.get(hf, at(T::steep, 10));
    if (plain && steep)
      c.check(hf, "",
              string_format("mean %.3f vs %.3f texels, p95 %.3f vs %.3f texels", steep->uv_error_mean,
                            plain->uv_error_mean, steep->uv_error_p95, plain->uv_error_p95),
              steep->uv_error_mean <= 0.5 * plain->uv_error_mean &&
                  steep->uv_error_p95 <= 0.5 * plain->uv_error_p95,
              ratio_text(std::max(steep->uv_error_mean / plain->uv_error_mean,
                                  steep->uv_error_p95 / plain->uv_error_p95),
                         1.0, "at most 0.5x"));
  }
  return c.finish();
}

// The fixed-count curve's mean uv error at a number of samples per ray, interpolated linearly in
// 1 / samples between the two measured fixed counts around it (a layered error falls as 1 / N);
// negative outside the measured range.
double fixed_curve_error(const ClaimBuilder& c, const std::string& hf, Technique technique, double samples,
                         std::string& between) {
  std::vector<const ClaimFigure*> fixed;
  for (int layers : kCurveLayers)
    if (const ClaimFigure* f = c.get(hf, at(technique, layers))) fixed.push_back(f);
  std::sort(fixed.begin(), fixed.end(),
            [](auto* a, auto* b) { return a->samples_per_ray < b->samples_per_ray; });
  for (std::size_t i = 0; i + 1 < fixed.size(); ++i) {
    const ClaimFigure &lo = *fixed[i], &hi = *fixed[i + 1];
    if (samples < lo.samples_per_ray || samples > hi.samples_per_ray || lo.samples_per_ray <= 0) continue;
    const double t =
        hi.samples_per_ray > lo.samples_per_ray
            ? (1 / samples - 1 / lo.samples_per_ray) / (1 / hi.samples_per_ray - 1 / lo.samples_per_ray)
            : 0.0;
    between = to_string(lo.row.layers) + " and " + to_string(hi.row.layers) + " layers";
    return lo.uv_error_mean + t * (hi.uv_error_mean - lo.uv_error_mean);
  }
  return -1.0;
}

ClaimResult claim_c5(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (Technique technique : {T::steep, T::relief, T::pom}) {
      const std::string name = to_string(technique);
      if (const ClaimFigure* dynamic = c.get(hf, at(technique, kDynamic))) {
        std::string between;
        const double curve = fixed_curve_error(c, hf, technique, dynamic->samples_per_ray, between);
        if (curve >= 0)
          c.check(hf, name + ", default view",
                  string_format("8-32: %.3f texels at %.2f samples/ray; fixed counts at the same samples: "
                                "%.3f texels (between ",
                                dynamic->uv_error_mean, dynamic->samples_per_ray, curve) +
                      between + ")",
                  dynamic->uv_error_mean <= curve, ratio_text(dynamic->uv_error_mean, curve, "at most 1x"));
      }
      for (double theta : kNearNormal) {
        const ClaimFigure *dynamic = c.get(hf, swept(technique, kDynamic, theta)),
                          *fixed = c.get(hf, swept(technique, 32, theta));
        if (dynamic && fixed)
          c.check(
              hf, name + string_format(", %.0f deg", theta),
              string_format("%.2f vs %.2f samples/ray, error %.3f vs %.3f texels", dynamic->samples_per_ray,
                            fixed->samples_per_ray, dynamic->uv_error_mean, fixed->uv_error_mean),
              dynamic->samples_per_ray <= 0.8 * fixed->samples_per_ray &&
                  close_in_quality(dynamic->uv_error_mean, fixed->uv_error_mean, 1.25),
              dynamic->samples_per_ray > 0.8 * fixed->samples_per_ray
                  ? ratio_text(dynamic->samples_per_ray, fixed->samples_per_ray, "samples at most 0.8x")
                  : ratio_text(dynamic->uv_error_mean, fixed->uv_error_mean,
                               "at most 1.25x or 0.25 texel more"));
      }
    }
  return c.finish();
}

ClaimResult claim_c6(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (int layers : {8, 16, 32})
      if (const ClaimFigure* f = c.get(hf, at(T::steep, layers)))
        c.check(hf, std::to_string(layers) + " layers",
                string_format("%.2f%% of rays within one layer", 100 * f->within_one_layer),
                f->within_one_layer >= 0.99,
                string_format("%.2f%%, against at least 99%%", 100 * f->within_one_layer));
  return c.finish();
}

ClaimResult claim_c7(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (int layers : {8, 16, 32}) {
      const ClaimFigure *pom = c.get(hf, at(T::pom, layers)), *steep = c.get(hf, at(T::steep, layers));
      if (pom && steep)
        c.check(hf, std::to_string(layers) + " layers",
                string_format("POM %.3f vs steep %.3f texels", pom->uv_error_mean, steep->uv_error_mean),
                pom->uv_error_mean <= 0.5 * steep->uv_error_mean,
                ratio_text(pom->uv_error_mean, steep->uv_error_mean, "at most 0.5x"));
    }
  return c.finish();
}

ClaimResult claim_c8(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (int layers : {8, 16, 32}) {
      const ClaimFigure *relief = c.get(hf, at(T::relief, layers)), *pom = c.get(hf, at(T::pom, layers)),
                        *steep = c.get(hf, at(T::steep, layers));
      if (!relief || !pom || !steep) continue;
      c.check(hf, std::to_string(layers) + " layers, accuracy",
              string_format("relief %.3f, POM %.3f, steep %.3f texels", relief->uv_error_mean,
                            pom->uv_error_mean, steep->uv_error_mean),
              relief->uv_error_mean <= std::min(pom->uv_error_mean, steep->uv_error_mean),
              ratio_text(relief->uv_error_mean, std::min(pom->uv_error_mean, steep->uv_error_mean),
                         "at most 1x"));
      c.check(hf, std::to_string(layers) + " layers, cost",
              string_format("relief %.2f vs POM %.2f samples/ray; ", relief->samples_per_ray,
                            pom->samples_per_ray) +
                  "relief " + speed(*relief) + " vs POM " + speed(*pom) + ": relief " +
                  compare_speeds(*relief, *pom),
              relief->samples_per_ray > pom->samples_per_ray &&
                  relief->samples_per_ray <= 2.0 * pom->samples_per_ray,
              ratio_text(relief->samples_per_ray, pom->samples_per_ray, "above 1x, at most 2x"));
    }
  return c.finish();
}

// C9's quality: the mean uv error close to relief's (close_in_quality) and, since the revision of
// this release, the wrong-surface rate too: at most 1.5x relief's or at most kCloseWrongSurface
// more (docs/claims.md#c9).
constexpr double kCloseWrongSurface = 0.001;  // a tenth of a percentage point: one pixel in a thousand

ClaimResult evaluate_c9(const Claim& claim, const ClaimsData& d, bool with_wrong_surface) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (int layers : {8, 16, 32}) {
      const ClaimFigure *relief = c.get(hf, at(T::relief, layers)), *pom = c.get(hf, at(T::pom, layers));
      if (!relief || !pom) continue;
      const bool close_error = close_in_quality(pom->uv_error_mean, relief->uv_error_mean, 1.5);
      const bool close_wrong = pom->wrong_surface_rate <= 1.5 * relief->wrong_surface_rate ||
                               pom->wrong_surface_rate - relief->wrong_surface_rate <= kCloseWrongSurface;
      const bool fewer_samples = pom->samples_per_ray < relief->samples_per_ray;
      c.check(hf, std::to_string(layers) + " layers",
              string_format("error POM %.3f vs relief %.3f texels, wrong surface %.2f%% vs %.2f%%, ",
                            pom->uv_error_mean, relief->uv_error_mean, 100 * pom->wrong_surface_rate,
                            100 * relief->wrong_surface_rate) +
                  string_format("%.2f vs %.2f samples/ray; ", pom->samples_per_ray, relief->samples_per_ray) +
                  "POM " + speed(*pom) + " vs relief " + speed(*relief) + ": POM " +
                  compare_speeds(*pom, *relief),
              close_error && (close_wrong || !with_wrong_surface) && fewer_samples,
              !close_error
                  ? ratio_text(pom->uv_error_mean, relief->uv_error_mean, "at most 1.5x or 0.25 texel more")
              : with_wrong_surface && !close_wrong
                  ? string_format("wrong surface %.2f%% vs %.2f%%, against at most 1.5x or 0.1 point more",
                                  100 * pom->wrong_surface_rate, 100 * relief->wrong_surface_rate)
                  : ratio_text(pom->samples_per_ray, relief->samples_per_ray, "samples below 1x"));
    }
  return c.finish();
}

ClaimResult claim_c9(const Claim& claim, const ClaimsData& d) { return evaluate_c9(claim, d, true); }
ClaimResult claim_c9_mean_error_only(const Claim& claim, const ClaimsData& d) {
  return evaluate_c9(claim, d, false);
}

ClaimResult claim_c10(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (Technique technique : {T::steep, T::pom})
      for (int layers : {4, 8}) {
        const ClaimFigure *few = c.get(hf, at(technique, layers)), *many = c.get(hf, at(technique, 64));
        if (!few || !many) continue;
        auto tunnelling = [&](const std::string& what, double a, double b) {
          if (a < 0 || b < 0) return;
          c.check(hf, to_string(technique) + " " + std::to_string(layers) + " vs 64 layers, " + what,
                  string_format("%.2f%% vs %.2f%% beyond one layer step (all rays: %.2f%% vs %.2f%%)",
                                100 * a, 100 * b, 100 * few->per_ray.beyond_one_layer,
                                100 * many->per_ray.beyond_one_layer),
                  a >= 2 * b && a >= b + 0.01,
                  string_format("%.2f%% vs %.2f%%, against at least 2x and 1 point more", 100 * a, 100 * b));
        };
        tunnelling(string_format("thin features (%.1f%% of rays)", 100 * few->per_ray.thin_share),
                   few->per_ray.thin_beyond_one_layer, many->per_ray.thin_beyond_one_layer);
        tunnelling("sharp depth changes", few->per_ray.sharp_beyond_one_layer,
                   many->per_ray.sharp_beyond_one_layer);
      }
  return c.finish();
}

const std::vector<LayerSpec> kConeLayers = [] {
  std::vector<LayerSpec> layers = fixed({4, 8, 10, 16, 32, 64});
  layers.push_back(kDynamic);
  return layers;
}();

ClaimResult claim_p1(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields()) {
    const ClaimFigure* relief = c.get(hf, at(T::relief, 32));
    if (!relief) continue;
    const ClaimFigure* cheapest = nullptr;
    for (const LayerSpec& layers : kConeLayers)
      if (const ClaimFigure* cone = c.get(hf, at(T::cone, layers));
          cone && cone->uv_error_mean <= relief->uv_error_mean + 0.05 &&
          (!cheapest || cone->samples_per_ray < cheapest->samples_per_ray))
        cheapest = cone;
    if (cheapest)
      c.check(hf, "",
              string_format(
                  "cone %s: %.3f texels at %.2f samples/ray; relief 32: %.3f texels at %.2f samples/ray",
                  to_string(cheapest->row.layers).c_str(), cheapest->uv_error_mean, cheapest->samples_per_ray,
                  relief->uv_error_mean, relief->samples_per_ray),
              cheapest->samples_per_ray <= 0.5 * relief->samples_per_ray,
              ratio_text(cheapest->samples_per_ray, relief->samples_per_ray, "at most 0.5x"));
    else if (c.get(hf, at(T::cone, 32)))
      c.check(hf, "",
              string_format("no cone configuration within 0.05 texel of relief 32's %.3f texels",
                            relief->uv_error_mean),
              false, "no cone as accurate");
  }
  return c.finish();
}

ClaimResult claim_p2(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  auto exact = [&](const std::string& hf, const std::string& at_size, const ClaimFigure* f) {
    if (f)
      c.check(hf, at_size + "exact",
              string_format("p99 %.2g texel (mean %.2g, wrong surface %.3f%%)", f->uv_error_p99,
                            f->uv_error_mean, 100 * f->wrong_surface_rate),
              f->uv_error_p99 <= kExactUvErrorP99,
              string_format("p99 %.2g, against at most %g", f->uv_error_p99, kExactUvErrorP99));
  };
  for (const std::string& hf : c.heightfields()) exact(hf, "", c.get(hf, at(T::maxmip, 1)));
  for (const std::string& hf : c.heightfields(true)) {
    const ClaimFigure* maxmip = c.get(hf, on_large_map(T::maxmip, 1));
    const std::string size =
        string_format("%d x %d, ", kLargeMapSide, kLargeMapSide);  // where_text says "at"
    exact(hf, size, maxmip);
    const ClaimFigure *equal = nullptr, *closest = nullptr;
    for (int layers : kLargeMapLayers)
      for (Technique technique : {T::relief, T::secant}) {
        const ClaimFigure* f = c.get(hf, on_large_map(technique, layers));
        if (!f) continue;
        if (f->uv_error_p99 <= kExactUvErrorP99 && (!equal || f->rays_per_second > equal->rays_per_second))
          equal = f;
        if (!closest || f->uv_error_p99 < closest->uv_error_p99) closest = f;
      }
    const ClaimFigure* linear = equal ? equal : closest;
    if (!maxmip || !linear) continue;
    const std::string speeds = compare_speeds(*maxmip, *linear);
    c.check(hf, size + "speed",
            string_format("maxmip %.2f samples/ray, p99 %.2g texel; ", maxmip->samples_per_ray,
                          maxmip->uv_error_p99) +
                to_string(linear->row.technique) + " " + to_string(linear->row.layers) +
                string_format(" (%s): %.2f samples/ray, p99 %.2g texel; maxmip ",
                              equal ? "as accurate" : "the most accurate", linear->samples_per_ray,
                              linear->uv_error_p99) +
                speed(*maxmip) + " vs " + speed(*linear) + ": maxmip " + speeds,
            speeds == "faster", "maxmip " + speeds);
  }
  return c.finish();
}

ClaimResult claim_p3(const Claim& claim, const ClaimsData& d) {
  ClaimBuilder c(claim, d);
  for (const std::string& hf : c.heightfields())
    for (int layers : {4, 8, 16, 32}) {
      const ClaimFigure* secant = c.get(hf, at(T::secant, layers));
      if (!secant) continue;
      std::string between;
      const double relief = fixed_curve_error(c, hf, T::relief, secant->samples_per_ray, between);
      if (relief >= 0)
        c.check(
            hf, "secant " + std::to_string(layers) + " layers",
            string_format(
                "secant %.4f texels at %.2f samples/ray; relief at the same samples: %.4f texels (between ",
                secant->uv_error_mean, secant->samples_per_ray, relief) +
                between + ")",
            secant->uv_error_mean < relief, ratio_text(secant->uv_error_mean, relief, "below 1x"));
    }
  return c.finish();
}

// The rows a fixed-count curve of fixed_curve_error() reads.
std::vector<ClaimRow> curve_rows(Technique technique) {
  std::vector<ClaimRow> out;
  for (int layers : kCurveLayers) out.push_back(at(technique, layers));
  return out;
}

std::vector<Claim> make_claims() {
  const ClaimView sweep = ClaimView::sweep;
  std::vector<Claim> list;
  list.push_back(
      {"C1",
       "plain parallax is a rough approximation that breaks at steep view angles and sharp depth changes",
       "LearnOpenGL",
       "Per heightfield. Steep angles: plain parallax's relative error (mean uv error / mean |T - T*|, both "
       "in "
       "texels, on sweep views) at 70 and 80 degrees is at least 2x that at 20 and 30 degrees. Sharp depth "
       "changes: at the default view, its mean uv error on the rays whose |grad D| at the exact hit is in "
       "the "
       "field's top decile is at least 2x that on the rays in the field's bottom half.",
       rows({T::parallax}, fixed({1}), sweep, {20, 30, 70, 80}) + rows({T::parallax}, fixed({1})), claim_c1});
  list.push_back(
      {"C2", "offset limiting gives better results than plain parallax at grazing angles",
       "LearnOpenGL; POM in GLSL",
       "Per heightfield and grazing angle (70, 80 degrees): parallax-limited's mean uv error is below plain "
       "parallax's.",
       rows({T::parallax, T::parallax_limited}, fixed({1}), sweep, {70, 80}), claim_c2});
  list.push_back(
      {"C3", "steep parallax's accuracy grows with the number of layers", "LearnOpenGL; Steep PM notes",
       "Per heightfield and each doubling 4 -> 8 -> 16 -> 32 -> 64: steep's mean uv error decreases.",
       rows({T::steep}, fixed({4, 8, 16, 32, 64})), claim_c3});
  list.push_back(
      {"C4", "about 10 layers already make steep parallax look far more correct than plain parallax",
       "LearnOpenGL",
       "Per heightfield at the default view: steep with 10 layers has at most half of plain parallax's mean "
       "uv "
       "error and at most half of its p95 uv error (the typical ray and the visible outliers; not the share "
       "over one texel, which steep's expected stair-stepping of several texels per layer at 10 layers "
       "would decide).",
       rows({T::parallax}, fixed({1})) + rows({T::steep}, fixed({10})), claim_c4});
  std::vector<ClaimRow> c5 =
      rows({T::steep, T::relief, T::pom}, {kDynamic}) +
      rows({T::steep, T::relief, T::pom}, {kDynamic, LayerSpec::fixed(32)}, sweep, {0, 10, 20, 30});
  for (Technique t : {T::steep, T::relief, T::pom}) c5 = c5 + curve_rows(t);
  list.push_back(
      {"C5",
       "view-dependent layer counts (8-32) save samples where few are needed, at little cost in accuracy",
       "LearnOpenGL; Steep PM notes",
       "Per heightfield and layered technique (steep, relief, POM). Pareto, at the default view: 8-32's mean "
       "uv "
       "error is at most that of the fixed layer counts' curve at the same samples per ray (interpolated in "
       "1 / samples between the two measured counts around it). Near-normal views (sweeps at 0, 10, 20, 30 "
       "degrees), where the tutorial places the saving: 8-32 takes at most 80% of the samples per ray of a "
       "fixed 32, and its mean uv error is close to 32's (at most 1.25x, or at most a quarter texel more).",
       c5, claim_c5});
  list.push_back(
      {"C6", "steep parallax shows stair-stepping: its error is bounded by about one layer",
       "LearnOpenGL; Steep PM notes",
       "Per heightfield and layer count (8, 16, 32): at least 99% of steep's rays have a uv error no larger "
       "than the texture step of one layer along their own ray.",
       rows({T::steep}, fixed({8, 16, 32})), claim_c6});
  list.push_back(
      {"C7", "POM is much more accurate than steep parallax at the same layer count",
       "LearnOpenGL; POM in GLSL",
       "Per heightfield and layer count (8, 16, 32): POM's mean uv error is at most half of steep's.",
       rows({T::pom, T::steep}, fixed({8, 16, 32})), claim_c7});
  list.push_back(
      {"C8",
       "relief mapping gives the most accurate results of the layered methods, at a somewhat higher cost "
       "than POM",
       "LearnOpenGL; POM in GLSL; Steep PM notes",
       "Per heightfield and layer count (8, 16, 32): relief's mean uv error is the lowest of steep, POM and "
       "relief, and relief's cost, in height samples per ray (deterministic; the speeds are shown as median "
       "(min-max) beside it, and decide nothing), is above POM's but at most twice it.",
       rows({T::relief, T::pom, T::steep}, fixed({8, 16, 32})), claim_c8});
  const char* c9_speeds =
      "(deterministic; the speeds are shown as median (min-max) beside it, and decide nothing).";
  list.push_back(
      {"C9", "POM is close to relief mapping in quality and faster, hence the more common choice",
       "LearnOpenGL; Steep PM notes",
       std::string(
           "Per heightfield and layer count (8, 16, 32): POM is close to relief in quality, its mean uv "
           "error at most 1.5x relief's or at most a quarter texel more, and its wrong-surface rate at "
           "most 1.5x relief's or at most 0.1 percentage point more; and POM takes fewer height "
           "samples per ray than relief ") +
           c9_speeds,
       rows({T::relief, T::pom}, fixed({8, 16, 32})), claim_c9,
       Claim::Revision{
           "the quality a player sees includes the pixels that show another surface, which the "
           "recommendation bounds (docs/recommendation.md); the mean uv error alone passed "
           "settings where POM lands on a wrong surface 7 to 13 times as often as relief",
           std::string("Per heightfield and layer count (8, 16, 32): POM's mean uv error is close "
                       "to relief's (at most 1.5x, or at most a quarter texel more) and POM takes "
                       "fewer height samples per ray than relief ") +
               c9_speeds,
           claim_c9_mean_error_only}});
  list.push_back(
      {"C10", "too few layers miss thin features and steep height changes", "LearnOpenGL; POM in GLSL",
       "Per heightfield, for steep and POM with 4 and 8 layers against 64: among the rays whose exact hit "
       "lies "
       "on a thin feature (the ray leaves the solid again within 1/8 of the depth range) and, separately, "
       "among the rays whose |grad D| at the exact hit is in the field's top decile, the share of rays off "
       "by "
       "more than one layer step (tunnelling: the layer search stepped over the first surface) is at least "
       "2x "
       "that with 64 layers and at least 1 percentage point above it. A field without at least 100 such "
       "rays does not take part in that check.",
       rows({T::steep, T::pom}, fixed({4, 8, 64})), claim_c10});
  std::vector<ClaimRow> p1 = rows({T::relief}, fixed({32}));
  for (const LayerSpec& layers : kConeLayers) p1.push_back(at(T::cone, layers));
  list.push_back(
      {"P1", "relaxed cone stepping matches relief mapping's accuracy with far fewer samples per ray",
       "Policarpo and Oliveira, GPU Gems 3 ch. 18 (2007)",
       "Per heightfield at the default view, against relief with 32 layers: the cheapest cone configuration "
       "(fewest height samples per ray among its measured layer specs) whose mean uv error matches "
       "relief-32's "
       "(at most relief-32's, or at most 0.05 texel more: no visible difference) takes at most half of "
       "relief-32's samples per ray. Fails where no cone configuration matches.",
       p1, claim_p1});
  std::vector<ClaimRow> p2 =
      rows({T::maxmip}, fixed({1})) + rows({T::maxmip}, fixed({1}), ClaimView::large_map);
  for (int layers : kLargeMapLayers)
    for (Technique t : {T::relief, T::secant}) p2.push_back(on_large_map(t, layers));
  list.push_back(
      {"P2",
       "maximum-mipmap tracing is exact, and on large depth maps faster than linear search at equal accuracy",
       "Tevs, Ihrke and Seidel, I3D 2008",
       string_format(
           "Exact: per heightfield, at the default view and on the large map, maxmip's p99 uv error is at "
           "most "
           "%g texel. Faster: per builtin at %d x %d (view %d x %d), maxmip's rays/s against the linear "
           "search "
           "of equal accuracy, relief and secant (linear layers, then binary or secant refinement) at 64, "
           "256 "
           "and 1024 layers: the fastest of those whose p99 uv error is at most %g texel, or, where none is, "
           "the most accurate one (equal accuracy would take it more layers, so more time). Passes when "
           "maxmip "
           "is faster with spreads apart; a time claim, so speeds decide it, and overlapping spreads fail "
           "it.",
           kExactUvErrorP99, kLargeMapSide, kLargeMapSide, kLargeMapViewSide, kLargeMapViewSide,
           kExactUvErrorP99),
       p2, claim_p2});
  list.push_back(
      {"P3", "secant refinement is more accurate than binary refinement at the same number of samples",
       "Risser, Shah and Pattanaik, Interval Mapping (2007)",
       "Per heightfield at the default view and secant layer count (4, 8, 16, 32; 5 refinement steps each): "
       "secant's mean uv error is below relief's (binary refinement, 5 halvings) at the same samples per "
       "ray, relief's error there interpolated in 1 / samples between its two measured layer counts around "
       "it; no check where secant's samples fall outside relief's measured range.",
       rows({T::secant}, fixed({4, 8, 16, 32})) + curve_rows(T::relief), claim_p3});
  return list;
}

}  // namespace

const std::vector<Claim>& claims() {
  static const std::vector<Claim> list = make_claims();
  return list;
}

std::vector<ClaimResult> evaluate_claims(const ClaimsData& data) {
  std::vector<ClaimResult> results;
  for (const Claim& claim : claims()) {
    ClaimResult r = claim.evaluate(claim, data);
    if (claim.revision) {
      const ClaimResult before = claim.revision->previous(claim, data);
      r.previous = ClaimResult::Previous{claim.revision->reason, claim.revision->previous_rule,
                                         before.summary, before.verdict};
    }
    results.push_back(std::move(r));
  }
  return results;
}

std::string claims_markdown(const std::vector<ClaimResult>& results, const std::string& provenance_line,
                            const std::string& configurations, const std::string& recommendation) {
  std::string md =
      "# The tutorials' and the papers' claims, measured\n\n" + provenance_line + "\n\n" + configurations +
      "\n\nEach rule was fixed in the source (src/claims/claims.cpp) before any figure was measured; "
      "docs/claims.md gives each claim's words and source (the tutorials C1-C10, the papers P1-P3) and "
      "argues the reading its rule implements. The verdict is *holds* when every check passes, *mostly "
      "holds* when at least " +
      string_format("%.0f%%", 100 * kMostlyShare) +
      " do, *mostly refuted* when "
      "at most " +
      string_format("%.0f%%", 100 * (1 - kMostlyShare)) +
      " do (but some), *refuted* when none "
      "do, and *holds partly* between; each says how many checks pass and where it fails "
      "(docs/claims.md#verdicts). A rule revised in this release shows the previous rule's verdict beside "
      "it.\n\n"
      "| claim | verdict | checks passed | where |\n|---|---|---|---|\n";
  for (const ClaimResult& r : results)
    md +=
        "| [" + r.id + "](#" + r.id + ") " + markdown_text(r.claim) + " | **" + to_string(r.verdict) +
        "** | " + std::to_string(r.passed) + " / " + std::to_string(r.checks.size()) + " | " +
        markdown_text(r.summary + (r.previous ? "; previous rule: " + to_string(r.previous->verdict) : "")) +
        " |\n";
  md += "\n## What to ship on these rows\n\n" + recommendation;
  for (const ClaimResult& r : results) {
    md += "\n<a id=\"" + r.id + "\"></a>\n## " + r.id + ": " + markdown_text(r.claim) + "\n\n";
    md += "Source: " + markdown_text(r.source) +
          " (docs/claims.md gives the words and the pages).\n\nRule: " + markdown_text(r.rule) + "\n\n";
    if (r.previous)
      md += "Revised in this release, because " + markdown_text(r.previous->reason) +
            ". The previous rule: " + markdown_text(r.previous->rule) + " Its verdict on these figures: **" +
            to_string(r.previous->verdict) + "** (" + markdown_text(r.previous->summary) + ").\n\n";
    if (!r.checks.empty()) {
      md += "| where | figures | deciding | passes |\n|---|---|---|---|\n";
      for (const ClaimCheck& c : r.checks)
        md += "| " + markdown_text(c.where()) + " | " + markdown_text(c.figures) + " | " +
              markdown_text(c.deciding) + " | " + (c.passed ? "yes" : "**no**") + " |\n";
    }
    // The summary names a mixed verdict first ("holds partly: holds on ..."): said once, in bold.
    std::string summary = r.summary;
    if (const std::string lead = to_string(r.verdict) + ": "; summary.rfind(lead, 0) == 0)
      summary.erase(0, lead.size());
    md += "\nVerdict: **" + to_string(r.verdict) + "**: " + markdown_text(summary) + ".\n";
  }
  return md;
}

std::string claims_json(const std::vector<ClaimResult>& results) {
  JsonWriter json;
  json.begin_object()
      .value("format", "heightmarch-claims")
      .value("format_version", kClaimsFormatVersion)
      .begin_array("claims");
  for (const ClaimResult& r : results) {
    json.begin_object()
        .value("id", r.id)
        .value("claim", r.claim)
        .value("source", r.source)
        .value("rule", r.rule);
    json.value("verdict", to_string(r.verdict)).value("passed", r.passed).value("checked", r.checks.size());
    json.value("summary", r.summary);
    json.begin_array("checks");
    for (const ClaimCheck& c : r.checks)
      json.begin_object()
          .value("where", c.where())
          .value("heightfield", c.heightfield)
          .value("at", c.at)
          .value("figures", c.figures)
          .value("deciding", c.deciding)
          .value("passed", c.passed)
          .end_object();
    json.end_array();
    if (r.previous)
      json.begin_object("previous")
          .value("reason", r.previous->reason)
          .value("rule", r.previous->rule)
          .value("verdict", to_string(r.previous->verdict))
          .value("summary", r.previous->summary)
          .end_object();
    else
      json.null("previous");
    json.end_object();
  }
  json.end_array().end_object();
  return json.str() + "\n";
}

}  // namespace heightmarch
