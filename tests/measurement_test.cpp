// The measurement pass: plans merge what is measured twice, every configuration is measured once
// for its accuracy and then timed in interleaved rounds, and names and spreads are as documented.
#include <gtest/gtest.h>

#include <cmath>

#include "baselines/naive_port.hpp"
#include "baselines/structured_pom.hpp"
#include "experiment/plan_runner.hpp"
#include "experiment/run_outputs.hpp"
#include "experiment/suite_plan.hpp"
#include "heightmarch/error.hpp"
#include "kernels/kernel_abi.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

Configuration small(Technique technique, const char* layers, unsigned purposes) {
  Configuration c;
  c.heightfield = parse_heightfield("builtin:bricks", 64);
  c.view = default_view(48, 40);
  c.params.technique = technique;
  c.params.layers = layers_for(technique, parse_layer_spec(layers));
  c.isa = best_isa();
  c.threads = 1;
  c.purposes = purposes;
  return c;
}

TEST(Plan, OneConfigurationIsMeasuredOnce) {
  std::vector<Configuration> plan;
  add_to_plan(plan, small(Technique::pom, "32", kPurposeMatrix));
  Configuration claims = small(Technique::pom, "32", kPurposeClaims);
  claims.timed = false;
  add_to_plan(plan, claims);
  add_to_plan(plan, small(Technique::pom, "8", kPurposeMatrix));
  Configuration other_threads = small(Technique::pom, "32", kPurposeIsa);
  other_threads.threads = 2;
  add_to_plan(plan, other_threads);
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_EQ(plan[0].purposes, kPurposeMatrix | kPurposeClaims);
  EXPECT_TRUE(plan[0].timed);
  // The technique of a run without one does not tell two configurations apart.
  Configuration a = small(Technique::pom, "32", 0), b = small(Technique::steep, "32", 0);
  a.kind = b.kind = RunKind::roofline;
  EXPECT_TRUE(a.same_measurement(b));
}

TEST(Plan, RoundsInterleaveAndEveryTimedRowHasItsRepetitions) {
  std::vector<Configuration> plan = {small(Technique::pom, "32", kPurposeMatrix),
                                     small(Technique::steep, "8", kPurposeMatrix),
                                     small(Technique::relief, "8", kPurposeSweep)};
  plan[2].timed = false;
  std::vector<std::string> steps;
  MeasureOptions options;
  options.repetitions = 5;
  options.min_seconds = 0.0;
  options.progress = [&](const std::string& what, std::size_t done, std::size_t total) {
    EXPECT_EQ(total, 3u + 2u * 5u);
    EXPECT_EQ(done, steps.size() + 1);
    steps.push_back(what);
  };
  const MeasuredPlan run = measure_plan(plan, options);
  ASSERT_EQ(run.rows.size(), 3u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(run.rows[i].seconds.size(), 5u);
    const Spread s = spread_of(run.rows[i].rays_per_second());
    EXPECT_GT(s.min, 0.0);
    EXPECT_LE(s.min, s.median);
    EXPECT_LE(s.median, s.max);
  }
  EXPECT_TRUE(run.rows[2].seconds.empty());
  for (const Measurement& m : run.rows) {
    EXPECT_TRUE(m.failure.empty()) << m.failure;
    ASSERT_TRUE(m.errors.has_value());
    EXPECT_TRUE(m.errors->within_one_layer_step.has_value());
    EXPECT_EQ(m.rays, run.rows[0].rays);  // one scene: the pixels whose ray meets the plane
    EXPECT_GT(m.rays, 48u * 40u * 9 / 10);
  }
  // Accuracy first, then round 1 of both timed rows, then round 2, ...
  ASSERT_EQ(steps.size(), 13u);
  for (int round = 0; round < 5; ++round) {
    const std::string tag = "(round " + std::to_string(round + 1) + ")";
    EXPECT_NE(steps[3 + 2 * round].find("pom-32"), std::string::npos) << steps[3 + 2 * round];
    EXPECT_NE(steps[3 + 2 * round].find(tag), std::string::npos) << steps[3 + 2 * round];
    EXPECT_NE(steps[4 + 2 * round].find("steep-8"), std::string::npos) << steps[4 + 2 * round];
  }
}

TEST(Plan, TheExactReferenceIsARowWithoutError) {
  Configuration c = small(Technique::pom, "32", kPurposeCommand);
  c.kind = RunKind::exact;
  MeasureOptions options;
  options.repetitions = 1;
  options.min_seconds = 0.0;
  const MeasuredPlan run = measure_plan({c}, options);
  ASSERT_TRUE(run.rows[0].errors.has_value());
  EXPECT_EQ(run.rows[0].errors->uv.max, 0.0);
  EXPECT_GT(run.rows[0].samples, 0u);  // cells solved
}

// The measures follow the hit list: the hit's, then two for each output measured against the
// light's visibility (the shadow factor's); a row carries them under the names measurements.json
// lists, NaN (null) where its technique does not write the output.
TEST(Registry, MeasuresFollowTheHitList) {
  std::vector<std::string> names;
  for (const ErrorMeasure& m : error_measure_list()) names.push_back(m.name);
  // Each distribution as NAME_mean .. NAME_max and its wrong rate, in the list's order.
  std::vector<std::string> expected;
  const auto distribution = [&](const std::string& name, const std::string& rate) {
    for (const char* statistic : {"mean", "rms", "p50", "p95", "p99", "max"})
      expected.push_back(name + "_" + statistic);
    expected.push_back(rate);
  };
  distribution("uv_error", "wrong_surface_rate");
  expected.push_back("depth_error_mean");
  distribution("pixel_error", "wrong_pixel_rate");
  distribution("search_error", "search_wrong_surface_rate");
  distribution("search_pixel_error", "search_wrong_pixel_rate");
  distribution("filter_bias", "filter_wrong_surface_rate");
  distribution("filter_pixel_bias", "filter_wrong_pixel_rate");
  expected.insert(expected.end(), {"shadow_error_mean", "shadow_mismatch_rate"});
  EXPECT_EQ(names, expected);
  std::vector<Configuration> plan;
  for (Technique t : {Technique::pom, Technique::shadow}) plan.push_back(small(t, "8", kPurposeCommand));
  MeasureOptions options;
  options.repetitions = 1;
  options.min_seconds = 0.0;
  const MeasuredPlan run = measure_plan(plan, options);
  for (const Measurement& row : run.rows) {
    const auto measures = error_measures(*row.errors);
    ASSERT_EQ(measures.size(), names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      EXPECT_EQ(measures[i].first, names[i]);
      const bool shadow_measure = names[i].rfind("shadow_", 0) == 0;
      EXPECT_EQ(std::isnan(measures[i].second),
                shadow_measure && row.config.params.technique == Technique::pom)
          << names[i];
    }
  }
  const std::string json = measurements_json(run, "test");
  const std::size_t measures_at = json.find("\"measures\": [");
  ASSERT_NE(measures_at, std::string::npos);
  std::size_t at = measures_at;
  for (const ErrorMeasure& m : error_measure_list()) {  // in order, each with its label
    at = json.find("\"name\": \"" + m.name + "\",", at);
    ASSERT_NE(at, std::string::npos) << m.name;
    EXPECT_EQ(json.find("\"label\": ", at), json.find("\"label\": \"" + m.label + "\"", at)) << m.name;
  }
}

// The ISA list names its CPU features, and src/registry/isa.cpp checks every one of them in C++.
TEST(Registry, EveryIsasCpuFeaturesAreChecked) {
  for (Isa isa : all_isas()) EXPECT_NO_THROW(cpu_supports(isa)) << to_string(isa);
  EXPECT_TRUE(cpu_supports(Isa::scalar));
  EXPECT_EQ(isa_named("scalar"), Isa::scalar);
  EXPECT_THROW(isa_named("auto"), InputError);  // a name of the list, whichever CPU: never "the best here"
}

TEST(Plan, SpreadOfEvenAndOddCounts) {
  const Spread odd = spread_of({3.0, 1.0, 2.0});
  EXPECT_EQ(odd.median, 2.0);
  EXPECT_EQ(odd.min, 1.0);
  EXPECT_EQ(odd.max, 3.0);
  EXPECT_EQ(spread_of({4.0, 1.0, 2.0, 3.0}).median, 2.5);
  EXPECT_EQ(spread_of({}).median, 0.0);
}

TEST(Plan, BenchmarkNamesCarryTheSizes) {
  Configuration c = small(Technique::pom, "8-32", 0);
  c.isa = Isa::scalar;
  EXPECT_EQ(benchmark_name(c, 64, 64),
            "BM_Trace/heightfield:bricks/technique:pom/layers:8-32/isa:scalar/threads:1/view:48x40/"
            "depth_map:64x64");
  c.kind = RunKind::roofline;
  EXPECT_EQ(
      benchmark_name(c, 64, 64).rfind("BM_SamplerRoofline/heightfield:bricks/layers:8-32/isa:scalar/", 0),
      0u);
  c.kind = RunKind::ceiling;
  EXPECT_EQ(
      benchmark_name(c, 64, 64).rfind("BM_ComputeCeiling/heightfield:bricks/layers:8-32/isa:scalar/", 0), 0u);
  c.kind = RunKind::autovec;
  EXPECT_EQ(benchmark_name(c, 64, 64).rfind(
                "BM_AutoVecPort/heightfield:bricks/technique:pom/layers:8-32/isa:scalar/", 0),
            0u);
  c.kind = RunKind::highway;
  EXPECT_EQ(benchmark_name(c, 64, 64).rfind(
                "BM_HighwayPort/heightfield:bricks/technique:pom/layers:8-32/isa:scalar/", 0),
            0u);
  c.kind = RunKind::calibration;
  EXPECT_EQ(benchmark_name(c, 64, 64),
            "BM_Calibration/heightfield:bricks/isa:calibration/threads:1/view:48x40/depth_map:64x64");
}

// The calibration loop, scripts/compare's control: timed like any row, with nothing to check or
// measure but its time, at every thread count; every suite plan holds it at each of its thread
// counts on each heightfield.
TEST(Plan, TheCalibrationLoopIsTimedAndInEveryPlan) {
  std::vector<Configuration> plan;
  for (int threads : {1, 2}) {
    Configuration c = small(Technique::pom, "32", kPurposeCalibration);
    c.kind = RunKind::calibration;
    c.threads = threads;
    plan.push_back(c);
  }
  MeasureOptions options;
  options.repetitions = 2;
  options.min_seconds = 0.0;
  for (const Measurement& m : measure_plan(plan, options).rows) {
    EXPECT_TRUE(m.failure.empty()) << m.failure;
    EXPECT_FALSE(m.errors.has_value());
    EXPECT_FALSE(m.samples_known);
    ASSERT_EQ(m.seconds.size(), 2u);
    for (double s : m.seconds) EXPECT_GT(s, 0.0);
  }
  PlanSettings settings = suite_settings(true, 2);
  int calibrations = 0;
  for (const Configuration& c : suite_plan(settings))
    calibrations += c.kind == RunKind::calibration && c.timed;
  EXPECT_EQ(calibrations, int(settings.heightfields.size() * settings.thread_counts.size()));
}

// The anchors of POM-32 at every ISA: the auto-vectorised port and the Highway port (where this
// build has it) take the naive port's samples and land within its tolerance of the reference; the
// structured Highway POM (where it runs) equals the reference bit for bit (its backend checks);
// the ceiling is the same on every ISA and marches every ray to its bound (depth 1 everywhere).
TEST(Plan, AnchorsAreCheckedAtEveryIsa) {
  std::vector<Configuration> plan;
  Configuration naive = small(Technique::pom, "32", kPurposeNaive);
  naive.kind = RunKind::naive;
  plan.push_back(naive);
  for (Isa isa : supported_isas())
    for (RunKind kind : {RunKind::autovec, RunKind::highway, RunKind::highway_structured, RunKind::ceiling}) {
      if (kind == RunKind::highway && !highway_port_runs(isa)) continue;
      if (kind == RunKind::highway_structured && !highway_structured_runs(isa)) continue;
      Configuration c = small(Technique::pom, "32", kPurposeNaive);
      c.kind = kind;
      c.isa = isa;
      plan.push_back(c);
    }
  MeasureOptions options;
  options.repetitions = 1;
  options.min_seconds = 0.0;
  const MeasuredPlan run = measure_plan(plan, options);
  for (const Measurement& m : run.rows) {
    EXPECT_TRUE(m.failure.empty()) << m.failure;
    if (m.config.kind == RunKind::autovec || m.config.kind == RunKind::highway) {
      EXPECT_EQ(m.samples, run.rows[0].samples) << m.config.backend() << " " << to_string(m.config.kind);
    }
    if (m.config.kind == RunKind::ceiling) {
      EXPECT_FALSE(m.errors.has_value());
      EXPECT_GE(m.samples, m.rays * 34) << m.config.backend();  // 1 + ceil(32) + 1 steps + 1
    }
  }
}

// Every ISA exports a kernel for every registry row, filter and addressing mode.
TEST(Registry, EveryIsaHasEveryKernel) {
  for (Isa isa : all_isas()) {
    if (!cpu_supports(isa)) continue;  // the table of an ISA the CPU lacks is never touched
    const KernelTable& table = kernel_table(isa);
    for (int f = 0; f < kFilterCount; ++f) {
      for (const TechniqueInfo& t : techniques())
        for (int a = 0; a < kAddressingCount; ++a)
          EXPECT_NE(table.technique[int(t.id)][f][a], nullptr) << t.name;
      for (int a = 0; a < kAddressingCount; ++a) {
        EXPECT_NE(table.sampler_roofline[f][a], nullptr);
        EXPECT_NE(table.compute_ceiling[f][a], nullptr);
      }
    }
    EXPECT_NE(table.autovec_pom, nullptr);
  }
  for (const TechniqueInfo& t : techniques()) {
    EXPECT_EQ(parse_technique(std::string(t.name)), t.id);
    EXPECT_FALSE(t.glsl_call.empty());
    EXPECT_EQ(t.color.size(), 7u);
  }
}

}  // namespace
}  // namespace heightmarch
