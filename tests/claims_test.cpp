// The claims' rules on synthetic figures give the expected verdicts.
#include <gtest/gtest.h>

#include "heightmarch/claims.hpp"

namespace heightmarch {
namespace {

ClaimFigure figure(const std::string& hf, const std::string& technique, const std::string& layers, double mean,
                   double rays_per_second = 1e7, double wrong = 0.0, double samples = 10.0, double theta = -1.0) {
  ClaimFigure f;
  f.heightfield = hf;
  f.technique = technique;
  f.layers = layers;
  f.uv_error_mean = mean;
  f.rays_per_second = rays_per_second;
  f.wrong_surface_rate = wrong;
  f.samples_per_ray = samples;
  f.theta = theta;
  return f;
}

const ClaimResult& claim(const std::vector<ClaimResult>& results, const std::string& id) {
  for (const ClaimResult& r : results)
    if (r.id == id) return r;
  throw std::runtime_error("no claim " + id);
}

TEST(Claims, NoFiguresMeansNotMeasured) {
  for (const ClaimResult& r : evaluate_claims(ClaimsData{})) EXPECT_EQ(r.verdict, Verdict::not_measured) << r.id;
}

TEST(Claims, PomMuchMoreAccurateThanSteep) {
  ClaimsData d;
  for (const char* layers : {"8", "16", "32"}) {
    d.figures.push_back(figure("bricks", "steep", layers, 1.0));
    d.figures.push_back(figure("bricks", "pom", layers, 0.2));           // 0.2 <= 0.5: passes
    d.figures.push_back(figure("terrain", "steep", layers, 1.0));
    d.figures.push_back(figure("terrain", "pom", layers, layers == std::string("8") ? 0.9 : 0.1));
  }
  EXPECT_EQ(claim(evaluate_claims(d), "C7").verdict, Verdict::holds_partly);
  for (ClaimFigure& f : d.figures)
    if (f.technique == "pom") f.uv_error_mean = 0.3;
  EXPECT_EQ(claim(evaluate_claims(d), "C7").verdict, Verdict::holds);
  for (ClaimFigure& f : d.figures)
    if (f.technique == "pom") f.uv_error_mean = 0.8;
  EXPECT_EQ(claim(evaluate_claims(d), "C7").verdict, Verdict::refuted);
}

TEST(Claims, PomCloseToReliefAndCheaper) {
  ClaimsData d;
  d.figures.push_back(figure("waves", "relief", "16", 0.10, 8e6, 0.0, 20.0));
  d.figures.push_back(figure("waves", "pom", "16", 0.14, 10e6, 0.0, 16.0));
  EXPECT_EQ(claim(evaluate_claims(d), "C9").verdict, Verdict::holds);
  d.figures[1].rays_per_second = 7e6;  // a slower timing alone decides nothing: cost is samples per ray
  EXPECT_EQ(claim(evaluate_claims(d), "C9").verdict, Verdict::holds);
  d.figures[1].samples_per_ray = 21.0;  // more samples than relief
  EXPECT_EQ(claim(evaluate_claims(d), "C9").verdict, Verdict::refuted);
}

TEST(Claims, SteepImprovesWithLayers) {
  ClaimsData d;
  double error = 2.0;
  for (const char* layers : {"4", "8", "16", "32", "64"}) d.figures.push_back(figure("spikes", "steep", layers, error /= 2));
  EXPECT_EQ(claim(evaluate_claims(d), "C3").verdict, Verdict::holds);
  d.figures.back().uv_error_mean = 1.0;  // 64 layers worse than 32
  EXPECT_EQ(claim(evaluate_claims(d), "C3").verdict, Verdict::holds_partly);
}

TEST(Claims, DynamicLayersSaveSamples) {
  ClaimsData d;
  for (const char* technique : {"steep", "relief", "pom"}) {
    d.figures.push_back(figure("toybox", technique, "32", 0.5, 1e7, 0.0, 30.0));
    d.figures.push_back(figure("toybox", technique, "8-32", 0.55, 1e7, 0.0, 18.0));
  }
  EXPECT_EQ(claim(evaluate_claims(d), "C5").verdict, Verdict::holds);
  d.figures[1].samples_per_ray = 29.0;  // steep 8-32 saves nothing
  EXPECT_EQ(claim(evaluate_claims(d), "C5").verdict, Verdict::holds_partly);
}

TEST(Claims, OffsetLimitingAtGrazingAngles) {
  ClaimsData d;
  for (double theta : {70.0, 80.0}) {
    d.figures.push_back(figure("bricks", "parallax", "1", 5.0, 1e7, 0.0, 1.0, theta));
    d.figures.push_back(figure("bricks", "parallax-limited", "1", 2.0, 1e7, 0.0, 1.0, theta));
  }
  EXPECT_EQ(claim(evaluate_claims(d), "C2").verdict, Verdict::holds);
  const std::string md = claims_markdown(evaluate_claims(d), "provenance", "configurations");
  EXPECT_NE(md.find("Rule: Per heightfield and grazing angle"), std::string::npos);
  EXPECT_LT(md.find("Rule:"), md.find("limited 2.000 vs plain 5.000"));  // the rule precedes the figures
}

}  // namespace
}  // namespace heightmarch
