#pragma once
// The tutorials' claims C1-C10 and the papers' claims P1-P3 (the project's docs/claims.md gives
// each one's words, source and reading): the rows each claim reads, declared as typed values
// (the claims' plan is made of them), the rule that decides each verdict (fixed here, before any
// figure is seen) and the verdicts. Adding a claim: one entry of the table in claims.cpp (its
// words, rows and rule) and its reading in docs/claims.md.
#include <optional>
#include <string>
#include <vector>

#include "heightmarch/technique.hpp"

namespace heightmarch {

// Where a claim's row is measured: the default perspective view, a sweep view (one fixed angle
// theta from the normal over a grid of entry points), or for P2 the default view of a builtin
// at kLargeMapSide.
enum class ClaimView { default_view, sweep, large_map };

// One row a claim reads on each heightfield: a technique at a layer spec on a view.
struct ClaimRow {
  Technique technique = Technique::pom;
  LayerSpec layers;  // as the technique runs it (layers_for: "1" for one-sample techniques)
  ClaimView view = ClaimView::default_view;
  double theta = 0;  // sweep views: degrees from the normal
  friend bool operator==(const ClaimRow&, const ClaimRow&) = default;
};
std::string describe(const ClaimRow& row);  // "pom 32", "parallax 1 at 70 deg", "relief 64 on the large map"

// P2 (maximum mipmaps on large depth maps): the builtins at this side, on the default view at
// kLargeMapViewSide.
inline constexpr int kLargeMapSide = 2048;
inline constexpr int kLargeMapViewSide = 512;
// P2: "exact" is a p99 uv error at most this, in texels (float rounding, far below what shows).
inline constexpr double kExactUvErrorP99 = 1e-3;

// One measured row of a claim on one heightfield.
struct ClaimFigure {
  std::string heightfield;
  ClaimRow row;
  double uv_error_mean = 0, uv_error_p95 = 0, uv_error_p99 = 0, wrong_surface_rate = 0;
  double samples_per_ray = 0;
  double rays_per_second = 0, rays_per_second_min = 0,
         rays_per_second_max = 0;  // median and spread; 0: not timed
  double within_one_layer = 0;     // share of rays whose uv error is at most one layer's step

  // Figures per ray, measured from the depth map and the exact hits (never from names).
  struct PerRay {
    double offset_mean = 0;  // mean |T - T*| in texels: how far the exact hit lies from the entry point
    // Mean uv error on the rays whose |grad D| at the exact hit is in the top decile of this view's
    // rays ("sharp") and in its bottom half ("smooth"); negative when the field has no spread of
    // |grad D| (a flat map: no sharp changes to speak of).
    double sharp_error_mean = -1, smooth_error_mean = -1;
    // Layered techniques: share of rays off by more than one layer step (tunnelling), among all
    // rays, among the sharp rays and among the thin-feature rays (the exact hit lies on solid that
    // the ray leaves again within 1/8 of the depth range: thinner than one layer at 8 layers);
    // negative where that set has fewer than kMinFeatureRays rays (too few to speak).
    double beyond_one_layer = 0, sharp_beyond_one_layer = -1, thin_beyond_one_layer = -1;
    double thin_share = 0;  // share of the view's rays whose exact hit is on a thin feature
  } per_ray;
};

inline constexpr int kMinFeatureRays = 100;

struct ClaimsData {
  std::vector<ClaimFigure> figures;  // every view's, the large maps' included
  const ClaimFigure* find(const std::string& heightfield, const ClaimRow& row) const;
  // The heightfields with figures, in first-seen order: at their own size (default and sweep
  // views), or with large_maps those of the large maps (builtins at kLargeMapSide, named as at
  // their own size).
  std::vector<std::string> heightfields(bool large_maps = false) const;
};

// On the share of a claim's checks that pass (docs/claims.md#verdicts): holds (all), mostly holds (at
// least kMostlyShare), holds partly (between), mostly refuted (at most 1 - kMostlyShare, some),
// refuted (none).
enum class Verdict { holds, mostly_holds, holds_partly, mostly_refuted, refuted, not_measured };
inline constexpr double kMostlyShare = 0.75;
std::string to_string(Verdict verdict);
Verdict verdict_of(std::size_t passed, std::size_t checks);

struct ClaimCheck {
  std::string heightfield;
  std::string at;       // where on it, e.g. "32 layers" (empty: the heightfield as a whole)
  std::string figures;  // e.g. "POM 0.21 vs steep 1.30 texels"
  bool passed;
  std::string deciding;       // the figure that decides, against its bound: "0.54x, against at most 0.5x"
  std::string where() const;  // "bricks, 32 layers"
};

struct ClaimResult {
  std::string id, claim, source, rule;
  std::vector<ClaimCheck> checks;
  Verdict verdict = Verdict::not_measured;
  std::size_t passed = 0;
  // The verdict with its count and where it fails (or, mostly refuted, where it holds): "holds on
  // 13 of 15 checks; fails at 8 layers on bricks (0.54x, against at most 0.5x) and toybox (...)".
  std::string summary;
  // A rule revised in this release: why, the previous rule's words, and its verdict on the same
  // figures, shown beside the new one (never silently).
  struct Previous {
    std::string reason, rule, summary;
    Verdict verdict = Verdict::not_measured;
  };
  std::optional<Previous> previous;
};

// A claim: its words and source, the rule it implements (fixed before any figure is seen), the
// rows it reads on every heightfield (large-map rows only on the builtins) and what decides it;
// where its rule was revised, why and the previous rule.
struct Claim {
  std::string id, claim, source, rule;
  std::vector<ClaimRow> rows;
  ClaimResult (*evaluate)(const Claim& claim, const ClaimsData& data);
  struct Revision {
    std::string reason, previous_rule;
    ClaimResult (*previous)(const Claim& claim, const ClaimsData& data);
  };
  std::optional<Revision> revision = std::nullopt;
};
// C1-C10 and P1-P3, in order.
const std::vector<Claim>& claims();

// Applies every claim's rule to the figures: a verdict on the share of its checks that pass
// (verdict_of), not measured without checks; a revised rule's previous verdict beside it. Deterministic: the
// same figures give the same results (speeds never decide a verdict but P2's, a claim about time).
std::vector<ClaimResult> evaluate_claims(const ClaimsData& data);

// "faster", "slower" or "not distinguishable (spreads overlap)": a's speed against b's, from
// median and min-max of the timed repetitions; "not timed" without timings.
std::string compare_speeds(const ClaimFigure& a, const ClaimFigure& b);

// claims.md: the verdicts, the recommendation over the same rows (Markdown, recommendation.hpp),
// then each claim's rule and checks.
std::string claims_markdown(const std::vector<ClaimResult>& results, const std::string& provenance_line,
                            const std::string& configurations, const std::string& recommendation);
// claims.json: {"format": "heightmarch-claims", "format_version": 3, "claims": [...]} (version 1
// was the bare list; version 3 added the count, the summary, each check's heightfield, place and
// deciding figure, and a revised rule's previous verdict).
inline constexpr int kClaimsFormatVersion = 3;
std::string claims_json(const std::vector<ClaimResult>& results);

}  // namespace heightmarch
