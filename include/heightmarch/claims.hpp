#pragma once
// The tutorials' claims C1-C10 (SPEC section 7): the figures measured for them, the rule that
// decides each verdict (fixed here, before any figure is seen) and the verdicts.
#include <string>
#include <vector>

namespace heightmarch {

// One measured configuration. theta < 0: the default perspective view; else a sweep view.
struct ClaimFigure {
  std::string heightfield, technique, layers;
  double theta = -1.0;
  double uv_error_mean = 0, uv_error_p95 = 0, wrong_surface_rate = 0;
  double samples_per_ray = 0;
  double rays_per_second = 0, rays_per_second_min = 0, rays_per_second_max = 0;  // median and spread; 0: not timed
  double within_one_layer = 0;  // share of rays whose uv error is at most one layer's step
};

struct ClaimsData {
  std::vector<ClaimFigure> figures;
  const ClaimFigure* find(const std::string& heightfield, const std::string& technique, const std::string& layers,
                          double theta = -1.0) const;
  std::vector<std::string> heightfields() const;  // in first-seen order
};

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
};

// Applies every claim's rule to the figures: holds when every check passes, holds partly when
// some do, refuted when none do, not measured without checks.
std::vector<ClaimResult> evaluate_claims(const ClaimsData& data);

// The layer specs and angles the rules look at, so measurement and rules agree.
const std::vector<std::string>& claim_layer_specs();
const std::vector<double>& claim_sweep_angles();

std::string claims_markdown(const std::vector<ClaimResult>& results, const std::string& provenance_line,
                            const std::string& configurations);
std::string claims_json(const std::vector<ClaimResult>& results);

}  // namespace heightmarch
