#pragma once
// The tutorials' claims C1-C10 and the papers' claims P1-P3 (the project's docs/claims.md gives
// each one's words, source and reading): the figures measured for them, the rule that decides each
// verdict (fixed here, before any figure is seen) and the verdicts. Adding a claim: one rule
// function and one row of the table in claims.cpp.
#include <optional>
#include <string>
#include <vector>

namespace heightmarch {

// One measured configuration. theta < 0: the default perspective view; else a sweep view.
struct ClaimFigure {
  std::string heightfield, technique, layers;
  double theta = -1.0;
  double uv_error_mean = 0, uv_error_p95 = 0, uv_error_p99 = 0, wrong_surface_rate = 0;
  double samples_per_ray = 0;
  double rays_per_second = 0, rays_per_second_min = 0, rays_per_second_max = 0;  // median and spread; 0: not timed
  double within_one_layer = 0;  // share of rays whose uv error is at most one layer's step

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
  std::vector<ClaimFigure> figures;
  // P2's rows on large depth maps (the builtins at kLargeMapSide), apart from the others: the
  // same heightfield names at another size.
  std::vector<ClaimFigure> large_maps;
  const ClaimFigure* find(const std::string& heightfield, const std::string& technique, const std::string& layers,
                          double theta = -1.0) const;
  const ClaimFigure* find_on_large_map(const std::string& heightfield, const std::string& technique,
                                       const std::string& layers) const;
  std::vector<std::string> heightfields() const;            // in first-seen order
  std::vector<std::string> large_map_heightfields() const;  // in first-seen order
};

// P2 (maximum mipmaps on large depth maps): the builtins at this side, on the default view at
// kLargeMapViewSide, against linear searches with these layer counts (up to about one layer per
// texel the rays cross there).
inline constexpr int kLargeMapSide = 2048;
inline constexpr int kLargeMapViewSide = 512;
const std::vector<std::string>& claim_large_map_layer_specs();
// P2: "exact" is a p99 uv error at most this, in texels (float rounding, far below what shows).
inline constexpr double kExactUvErrorP99 = 1e-3;

enum class Verdict { holds, holds_partly, refuted, not_measured };
std::string to_string(Verdict verdict);

struct ClaimCheck {
  std::string where;    // e.g. "bricks, 32 layers"
  std::string figures;  // e.g. "POM 0.21 vs steep 1.30 texels"
  bool passed;
};

struct ClaimResult {
  std::string id, claim, source, rule;
  std::vector<ClaimCheck> checks;
  Verdict verdict = Verdict::not_measured;
  // This release only: the rule of the previous reading and its verdict on the same figures,
  // where the reading changed.
  std::string previous_rule;
  std::optional<Verdict> previous_verdict;
};

// Applies every claim's rule to the figures: holds when every check passes, holds partly when
// some do, refuted when none do, not measured without checks. Deterministic: the same figures
// give the same results (speeds never decide a verdict).
std::vector<ClaimResult> evaluate_claims(const ClaimsData& data);

// The layer specs and angles the rules look at, so measurement and rules agree.
const std::vector<std::string>& claim_layer_specs();
const std::vector<double>& claim_sweep_angles();          // plain and offset-limited parallax
const std::vector<double>& claim_near_normal_angles();    // layered techniques at 8-32 and 32 (C5)

// "faster", "slower" or "not distinguishable (spreads overlap)": a's speed against b's, from
// median and min-max of the timed repetitions; "not timed" without timings.
std::string compare_speeds(const ClaimFigure& a, const ClaimFigure& b);

std::string claims_markdown(const std::vector<ClaimResult>& results, const std::string& provenance_line,
                            const std::string& configurations);
std::string claims_json(const std::vector<ClaimResult>& results);

}  // namespace heightmarch
