// The recommendation: ranked by time per ray (never by samples per ray) among the configurations
// that meet both bounds, per heightfield and as one setting for all; the declared backends; the
// nearest configuration where none meets; and `heightmarch recommend` reading a run's
// measurements.json to the same answer the suite wrote from its rows. The suite's filters.
#include "experiment/recommendation.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "experiment/suite_plan.hpp"
#include "heightmarch/error.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// A candidate at the avx2 2-thread grid (or GLSL): its time per ray in ns over 5 rounds, its search
// error's p99 and wrong rate (in the target's unit) as given.
Candidate row(int id, const std::string& hf, Technique t, const char* layers, double ns, double p99,
              double wrong, double samples = 10.0, RunKind kind = RunKind::trace, int threads = 2,
              Filter filter = Filter::bilinear) {
  Candidate c;
  c.id = id;
  c.heightfield = hf;
  c.backend = {kind, kind == RunKind::trace ? Isa::avx2 : Isa::scalar, threads, "", filter};
  c.grid = kind == RunKind::trace;
  c.technique = t;
  c.layers = layers_for(t, parse_layer_spec(layers));
  c.filter = filter;
  c.selection.search.values[int(ErrorPercentile::p99)] = p99;
  c.selection.search.values[int(ErrorPercentile::max)] = 10 * p99;
  c.selection.search.wrong_rate = wrong;
  c.selection.total = c.selection.search;
  c.samples_per_ray = samples;
  c.rays = 1000;
  for (double f : {1.0, 1.02, 0.98, 1.01, 0.99}) c.seconds.push_back(ns * f * 1e-9 * double(c.rays));
  return c;
}

const BackendRecommendation& cpu(const Recommendation& r) { return r.backends.at(0); }

TEST(Recommendation, FastestByTimeNotBySamples) {
  // cone takes fewer samples but more time than relief: relief is the answer.
  const std::vector<Candidate> rows = {row(0, "bricks", Technique::cone, "10", 11.6, 0.3, 0.001, 7.9),
                                       row(1, "bricks", Technique::relief, "10", 6.1, 0.4, 0.002, 15.0),
                                       row(2, "bricks", Technique::pom, "8", 3.0, 0.2, 0.02, 9.0)};
  const Recommendation r = recommend(rows, RecommendationTarget{});
  ASSERT_EQ(r.backends.size(), 1u);
  const Answer& a = cpu(r).per_heightfield.at(0);
  ASSERT_TRUE(a.choice);
  EXPECT_EQ(a.choice->label(), "relief 10");
  EXPECT_EQ(a.meeting, 2) << "pom 8 has 2% wrong surface";
  ASSERT_TRUE(a.runner_up && a.runner_up_ratio);
  EXPECT_EQ(a.runner_up->label(), "cone 10");
  EXPECT_NEAR(a.runner_up_ratio->ratio, 11.6 / 6.1, 1e-9) << "the ratio of the median times";
  EXPECT_NEAR(a.runner_up_ratio->per_round.median, 11.6 / 6.1, 1e-9);
  EXPECT_NEAR(a.choice->time().median, 6.1e-9, 1e-15);
}

TEST(Recommendation, BothBoundsApply) {
  RecommendationTarget target;  // p99 <= 0.5 pixel, wrong pixel <= 0.5%
  const std::vector<Candidate> rows = {
      row(0, "bricks", Technique::pom, "10", 3.0, 0.4, 0.047),  // p99 fine, 4.7% wrong
      row(1, "bricks", Technique::pom, "16", 4.0, 0.9, 0.004),  // few wrong, p99 too big
      row(2, "bricks", Technique::relief, "64", 9.0, 0.06, 0.004)};
  EXPECT_EQ(cpu(recommend(rows, target)).per_heightfield[0].choice->label(), "relief 64");
  target.max_wrong_rate = 0.05;
  EXPECT_EQ(cpu(recommend(rows, target)).per_heightfield[0].choice->label(), "pom 10");
  target.percentile = ErrorPercentile::max;  // max = 10 p99 here
  target.max_error = 5.0;
  EXPECT_EQ(cpu(recommend(rows, target)).per_heightfield[0].choice->label(), "pom 10");
  target.max_error = 1.0;
  EXPECT_EQ(cpu(recommend(rows, target)).per_heightfield[0].choice->label(), "relief 64");
}

TEST(Recommendation, OneSettingMeetsTheTargetOnEveryMap) {
  // pom 16 is fastest on waves but fails bricks; relief 32 meets both; maxmip meets both, slower.
  const std::vector<Candidate> rows = {row(0, "bricks", Technique::pom, "16", 3.0, 2.0, 0.03),
                                       row(1, "bricks", Technique::relief, "32", 8.0, 0.1, 0.003),
                                       row(2, "bricks", Technique::maxmip, "1", 25.0, 0.0, 0.0),
                                       row(3, "waves", Technique::pom, "16", 3.0, 0.2, 0.001),
                                       row(4, "waves", Technique::relief, "32", 6.0, 0.1, 0.001),
                                       row(5, "waves", Technique::maxmip, "1", 20.0, 0.0, 0.0)};
  const Recommendation r = recommend(rows, RecommendationTarget{});
  const BackendRecommendation& b = cpu(r);
  ASSERT_EQ(b.per_heightfield.size(), 2u);
  EXPECT_EQ(b.per_heightfield[0].choice->label(), "relief 32");
  EXPECT_EQ(b.per_heightfield[1].choice->label(), "pom 16");
  const Answer& all = b.all_heightfields;
  EXPECT_TRUE(all.heightfield.empty());
  EXPECT_EQ(all.settings, 3);
  EXPECT_EQ(all.meeting, 2);
  ASSERT_TRUE(all.choice);
  EXPECT_EQ(all.choice->label(), "relief 32");
  ASSERT_EQ(all.choice->rows.size(), 2u);
  EXPECT_EQ(all.choice->rows[0].id, 1);
  EXPECT_EQ(all.choice->rows[1].id, 4);
  EXPECT_NEAR(all.choice->time().median, 7e-9, 1e-15) << "the mean over the maps of the time per ray";
  EXPECT_EQ(all.runner_up->label(), "maxmip");
}

TEST(Recommendation, NoneMeetsNamesTheNearest) {
  const std::vector<Candidate> rows = {row(0, "bricks", Technique::steep, "8", 2.0, 30.0, 0.2),
                                       row(1, "bricks", Technique::relief, "64", 9.0, 0.06, 0.006)};
  const Recommendation r = recommend(rows, RecommendationTarget{});
  const Answer& a = cpu(r).per_heightfield[0];
  EXPECT_FALSE(a.choice);
  EXPECT_EQ(a.meeting, 0);
  ASSERT_TRUE(a.closest);
  EXPECT_EQ(a.closest->label(), "relief 64");
  const std::string text = recommendation_text(r);
  EXPECT_NE(text.find("none of 2 meets the target; the nearest: relief 64"), std::string::npos) << text;
}

TEST(Recommendation, DeclaredBackendsAreTheGridsAndGlslAtItsThreads) {
  const std::vector<Candidate> rows = {
      row(0, "bricks", Technique::pom, "32", 4.0, 0.2, 0.001),
      row(1, "bricks", Technique::pom, "32", 25.0, 0.2, 0.001, 10, RunKind::glsl, 2),
      row(2, "bricks", Technique::pom, "32", 40.0, 0.2, 0.001, 10, RunKind::glsl, 1)};
  const Recommendation r = recommend(rows, RecommendationTarget{});
  ASSERT_EQ(r.backends.size(), 2u) << "GLSL at one thread is not a grid's backend";
  EXPECT_EQ(r.backends[0].backend.name(), "avx2, 2 threads, bilinear");
  EXPECT_EQ(r.backends[1].backend.name(), "glsl, 2 threads, bilinear");
  const std::string json = recommendation_json(r);
  for (const char* key :
       {"\"format\": \"heightmarch-recommendation\"", "\"format_version\": 3",
        "\"measure\": \"search_pixel_error_p99\"", "\"wrong_measure\": \"search_wrong_pixel_rate\"",
        "\"unit\": \"pixels\"", "\"filter\": \"bilinear\"", "\"all_heightfields\"", "\"per_heightfield\"",
        "\"ns_per_ray\"", "\"precompute_ms_per_frame\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

// The held-out figures: the search error's p99 and wrong rate on the held-out set, with intervals.
Accuracy held_out(double p99, double wrong) {
  Accuracy a;
  a.search.values[int(ErrorPercentile::p99)] = p99;
  a.search.intervals[int(ErrorPercentile::p99)] = {0.9 * p99, 1.1 * p99};
  a.search.values[int(ErrorPercentile::max)] = 10 * p99;
  a.search.wrong_rate = wrong;
  a.search.wrong_ci = {0.9 * wrong, 1.1 * wrong};
  a.total = a.search;
  a.rays = 1000;
  return a;
}

// A configuration that meets the target on the window it was chosen on but not on the held-out
// views is not recommended: the answer moves to the next that holds and says so.
TEST(Recommendation, APlantedWindowOnlySettingIsNotRecommended) {
  std::vector<Candidate> rows = {row(0, "waves", Technique::pom, "8", 2.0, 0.30, 0.003),
                                 row(1, "waves", Technique::pom, "16", 3.0, 0.40, 0.004),
                                 row(2, "waves", Technique::relief, "16", 4.0, 0.20, 0.002),
                                 row(3, "waves", Technique::maxmip, "1", 9.0, 0.0, 0.0)};
  rows[0].held_out = held_out(0.70, 0.009);   // the plant: meets on the window only
  rows[1].held_out = held_out(0.45, 0.0055);  // misses the wrong-surface bound by 10%
  rows[2].held_out = held_out(0.25, 0.003);
  rows[3].held_out = held_out(0.0, 0.0);
  const Recommendation r = recommend(rows, RecommendationTarget{});
  const Answer& a = cpu(r).per_heightfield.at(0);
  ASSERT_TRUE(a.choice);
  EXPECT_EQ(a.choice->label(), "relief 16");
  EXPECT_TRUE(a.held_out_checked);
  EXPECT_EQ(a.meeting, 2);
  ASSERT_EQ(a.failed_held_out.size(), 2u);
  EXPECT_EQ(a.failed_held_out[0].label(), "pom 8");
  ASSERT_TRUE(a.near_miss);
  EXPECT_EQ(a.near_miss->pick.label(), "pom 16");
  EXPECT_NEAR(a.near_miss->margin, 1.1, 1e-9);
  EXPECT_EQ(a.near_miss->measure, "wrong pixel");
  const std::string text = recommendation_text(r);
  EXPECT_NE(text.find("not pom 8, pom 16, which meet the target on the window but not on the held-out views"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("the next that holds: relief 16"), std::string::npos) << text;
  EXPECT_NE(text.find("held-out p99 0.25 (0.225-0.275) pixel, wrong pixel 0.3% (0.27-0.33%)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("near miss pom 16: 1.33x faster, wrong pixel 10% over its bound"), std::string::npos)
      << text;
  const std::string json = recommendation_json(r);
  for (const char* key :
       {"\"held_out\": {", "\"search_pixel_error_p99_ci\": [", "\"search_wrong_pixel_ci\": [",
        "\"failed_held_out\": [", "\"near_miss\": {", "\"held_out_checked\": true", "\"format_version\": 3"})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  // Without held-out twins the window decides, and the answer says it was not checked.
  for (Candidate& c : rows) c.held_out.reset();
  const Recommendation window_only = recommend(rows, RecommendationTarget{});
  EXPECT_EQ(cpu(window_only).per_heightfield.at(0).choice->label(), "pom 8");
  EXPECT_NE(recommendation_text(window_only).find("(not checked on held-out views)"), std::string::npos);
}

// The choice and its runner-up's ratio read one statistic: a runner-up slower by median time
// reads slower, whatever its per-round ratios' median would say.
TEST(Recommendation, TheRunnerUpNeverReadsFasterThanTheChoice) {
  Candidate choice = row(0, "waves", Technique::pom, "32", 1.0, 0.2, 0.001);
  Candidate second = row(1, "waves", Technique::relief, "8", 1.0, 0.2, 0.001);
  choice.seconds = {1e-6, 1e-6, 1e-6, 3e-6, 3e-6};      // median 1 us
  second.seconds = {0.9e-6, 0.9e-6, 2e-6, 2e-6, 2e-6};  // median 2 us; per-round ratios' median 0.9
  const Recommendation r = recommend({choice, second}, RecommendationTarget{});
  const Answer& a = cpu(r).per_heightfield.at(0);
  ASSERT_TRUE(a.choice && a.runner_up_ratio);
  EXPECT_EQ(a.choice->label(), "pom 32");
  EXPECT_GE(a.runner_up_ratio->ratio, 1.0);
  EXPECT_FALSE(a.runner_up_ratio->distinguishable());
}

// Each filter has its own answer, side by side: a shader that samples level 0 and one that reads a
// mip chain ship different settings.
TEST(Recommendation, EachFilterItsOwnAnswer) {
  const std::vector<Candidate> rows = {
      row(0, "bricks", Technique::pom, "8", 2.0, 0.9, 0.02),
      row(1, "bricks", Technique::relief, "32", 6.0, 0.2, 0.002),
      row(2, "bricks", Technique::pom, "8", 2.5, 0.3, 0.001, 10, RunKind::trace, 2, Filter::trilinear),
      row(3, "bricks", Technique::relief, "32", 7.0, 0.1, 0.001, 10, RunKind::trace, 2, Filter::trilinear)};
  const Recommendation r = recommend(rows, RecommendationTarget{});
  ASSERT_EQ(r.backends.size(), 2u);
  EXPECT_EQ(r.backends[0].backend.name(), "avx2, 2 threads, bilinear");
  EXPECT_EQ(r.backends[1].backend.name(), "avx2, 2 threads, trilinear");
  EXPECT_EQ(r.backends[0].per_heightfield.at(0).choice->label(), "relief 32");
  EXPECT_EQ(r.backends[1].per_heightfield.at(0).choice->label(), "pom 8");
  EXPECT_EQ(r.backends[1].per_heightfield.at(0).settings, 2) << "a filter's answer reads its own rows";
}

// Under trilinear the filter's bias stands beside the search error; where it alone misses the target
// and outweighs the search, the answer says more layers do not change what a player sees.
TEST(Recommendation, FilterDominatedWhereTheBiasAloneMissesTheTarget) {
  std::vector<Candidate> rows = {
      row(0, "bricks", Technique::pom, "16", 3.0, 0.3, 0.002, 10, RunKind::trace, 2, Filter::trilinear),
      row(1, "waves", Technique::pom, "16", 3.0, 0.3, 0.002, 10, RunKind::trace, 2, Filter::trilinear)};
  rows[0].selection.bias.values[int(ErrorPercentile::p99)] = 2.5;  // bricks: mipmapping moves it 2.5 pixels
  rows[0].selection.bias.wrong_rate = 0.04;
  rows[1].selection.bias.values[int(ErrorPercentile::p99)] = 0.2;  // waves: a little
  const RecommendationTarget target;
  EXPECT_TRUE(filter_dominated(rows[0].selection, target));
  EXPECT_FALSE(filter_dominated(rows[1].selection, target));
  const Recommendation r = recommend(rows, target);
  const BackendRecommendation& b = r.backends.at(0);
  ASSERT_TRUE(b.per_heightfield.at(0).choice && b.per_heightfield.at(1).choice);
  EXPECT_TRUE(b.per_heightfield.at(0).filter_dominated);
  EXPECT_FALSE(b.per_heightfield.at(1).filter_dominated);
  EXPECT_TRUE(b.all_heightfields.filter_dominated) << "the one setting for all shows bricks too";
  const std::string text = recommendation_text(r);
  EXPECT_NE(text.find("bricks: pom 16: "), std::string::npos) << text;
  EXPECT_NE(text.find("; filter bias p99 2.5 pixel, wrong pixel 4%"), std::string::npos) << text;
  EXPECT_NE(text.find("; filter-dominated: more layers do not change what a player sees here\n"),
            std::string::npos)
      << text;
  EXPECT_NE(recommendation_json(r).find("\"filter_dominated\": true"), std::string::npos);
  // The search error outweighing the bias: the layers still matter.
  rows[0].selection.search.values[int(ErrorPercentile::p99)] = 3.0;
  EXPECT_FALSE(filter_dominated(rows[0].selection, target));
  // Under bilinear the bias is none, whatever a row says.
  rows[0].filter = rows[0].backend.filter = Filter::bilinear;
  rows[0].selection.search.values[int(ErrorPercentile::p99)] = 0.3;
  EXPECT_FALSE(recommend({rows[0]}, target).backends.at(0).per_heightfield.at(0).filter_dominated);
}

TEST(Recommendation, TargetsOutsideTheirRangeAreRefused) {
  RecommendationTarget t;
  t.max_wrong_rate = 1.5;
  EXPECT_THROW(validate(t), InputError);
  t = {};
  t.max_error = -1;
  EXPECT_THROW(validate(t), InputError);
  t = {};
  t.frames = 0;
  EXPECT_THROW(validate(t), InputError);
}

// `heightmarch recommend` reads the run's measurements.json back to the answer the suite wrote from
// its typed rows: one implementation, whichever way its rows come. Also: the suite's filters.
TEST(Recommendation, RecommendReadsARunToTheSuitesAnswer) {
  const std::string out = test::temp_dir("recommend") + "/run";
  const auto run = test::run_cli(
      "suite --quick --no-builtins --heightmap builtin:waves --techniques pom,relief,maxmip "
      "--layers 8,32 --isas scalar --threads 1 --parts matrix --repetitions 1 --no-glsl --out " +
      out);
  ASSERT_EQ(run.status, 0) << run.output;
  std::ifstream written(out + "/recommendation.json");
  const std::string suite_json((std::istreambuf_iterator<char>(written)), {});
  const auto again = test::run_cli("recommend " + out + " --json");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(again.output, suite_json);
  EXPECT_NE(suite_json.find("\"backend\": \"scalar\""), std::string::npos) << suite_json;
  // The suite keeps its rows compressed (measurements.json.gz); the same rows unpacked (as a claims
  // run writes them): the same answer; a cut file refused.
  ASSERT_FALSE(std::filesystem::exists(out + "/measurements.json"));
  const std::string plain = test::temp_dir("recommend-plain") + "/run";
  std::filesystem::create_directories(plain);
  ASSERT_EQ(
      std::system(("gzip -dc " + out + "/measurements.json.gz > " + plain + "/measurements.json").c_str()),
      0);
  const auto unpacked = test::run_cli("recommend " + plain + " --json");
  ASSERT_EQ(unpacked.status, 0) << unpacked.output;
  EXPECT_EQ(unpacked.output, suite_json);
  ASSERT_EQ(std::system(("head -c 2000 " + out + "/measurements.json.gz > " + plain + "/cut.gz").c_str()), 0);
  const auto cut = test::run_cli("recommend " + plain + "/cut.gz");
  EXPECT_EQ(cut.status, 2) << cut.output;
  EXPECT_NE(cut.output.find("not a whole gzip file"), std::string::npos) << cut.output;
  const auto other =
      test::run_cli("recommend " + out + " --percentile p95 --max-error 2 --max-wrong-surface 100");
  ASSERT_EQ(other.status, 0) << other.output;
  EXPECT_NE(other.output.find("at p95 <= 2 pixel, wrong pixel <= 100%"), std::string::npos) << other.output;
  const auto texels =
      test::run_cli("recommend " + out + " --unit texels --percentile p95 --max-error 2 --max-wrong 100");
  ASSERT_EQ(texels.status, 0) << texels.output;
  EXPECT_NE(texels.output.find("at p95 <= 2 texel, wrong surface <= 100%"), std::string::npos)
      << texels.output;
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"recommend " + out + " --percentile p90", "--percentile: p90 not in"},
           {"recommend " + out + " --max-wrong-surface 101",
            "--max-wrong: must be in [0, 100], not 101"},  // its former name, an alias
           {"recommend /nonexistent", "/nonexistent: cannot open measurements.json"}}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << ": " << r.output;
  }
}

// recommend reads measurements.json checked: a value out of its type or range is one line naming
// the row and the field, exit 2, never a figure (1e308 seconds read as inf ns/ray, -1 rays as 2^64-1,
// an id of 1e20 as -2147483648, a negative uv error counted within the bound); a FIFO is refused
// before it is read; a file larger than the memory budget allows is refused before it is parsed.
TEST(Recommendation, RecommendRefusesBadValuesInOneLine) {
  const std::string dir = test::temp_dir("recommend-bad-values");
  const std::string good =
      R"({"format": "heightmarch-measurements", "format_version": 2, "rows": [{"id": 0, "kind": "trace",)"
      R"( "purposes": ["matrix"], "technique": "pom", "layers": "32", "backend": "avx2", "threads": 2,)"
      R"( "heightfield": {"label": "bricks", "width": 32, "height": 32}, "view": {"kind": "default"},)"
      R"( "rays": 4096, "samples_per_ray": 10, "failure": null, "precompute_seconds": null,)"
      R"( "errors": {"uv_error_p50": 0.1, "uv_error_p95": 0.2, "uv_error_p99": 0.3, "uv_error_max": 1,)"
      R"( "wrong_surface_rate": 0.001}, "speed": {"seconds": [0.001, 0.0011, 0.0009]}}]})";
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const auto write = [&](const std::string& text) {
    std::ofstream(dir + "/measurements.json") << text;
    return test::run_cli("recommend " + dir + " --unit texels");
  };
  const auto fine = write(good);
  ASSERT_EQ(fine.status, 0) << fine.output;
  // A run of format 2 has no errors in pixels, and read level 0 as every filter's reference.
  const auto pixels = test::run_cli("recommend " + dir);
  EXPECT_EQ(pixels.status, 2) << pixels.output;
  EXPECT_NE(
      pixels.output.find("rows[0]: errors: has no errors in pixels (measured before they were): read it with "
                         "--unit texels"),
      std::string::npos)
      << pixels.output;
  const auto trilinear = write(with("\"threads\": 2,", "\"threads\": 2, \"filter\": \"trilinear\","));
  EXPECT_EQ(trilinear.status, 2) << trilinear.output;
  EXPECT_NE(trilinear.output.find("reads trilinear but was measured before the search error"),
            std::string::npos)
      << trilinear.output;
  for (const auto& [text, message] : std::vector<std::pair<std::string, std::string>>{
           {with("[0.001, 0.0011, 0.0009]", "[1e308, 0.0011, 0.0009]"),
            "rows[0]: speed.seconds: is 1e+308, not in (0,"},
           {with("[0.001, 0.0011, 0.0009]", "[]"),
            "rows[0]: speed.seconds: is not a list of repetitions' seconds"},
           {with("\"rays\": 4096", "\"rays\": -1"), "rows[0]: rays: is -1, not in 0.."},
           {with("\"id\": 0", "\"id\": 1e20"), "rows[0]: id: is 1e+20, not an integer"},
           {with("\"uv_error_p99\": 0.3", "\"uv_error_p99\": -5"),
            "rows[0]: errors.uv_error_p99: is -5, not in [0,"},
           {with("\"threads\": 2", "\"threads\": \"2\""), "rows[0]: threads: is \"2\", not an integer"},
           {with("0.0011", "NaN"), "not JSON"},
           {with("0.0011", "1e400"), "not JSON"},
           // read as an int, 2^32 + 2 was format 2
           {with("\"format_version\": 2", "\"format_version\": 4294967298"),
            "not a heightmarch measurements.json of format"},
           // quoted in its error line, it was dumped one recursion a level deep (a crash)
           {with("\"id\": 0", "\"id\": " + std::string(100000, '[') + std::string(100000, ']')),
            "nested deeper than 64"}}) {
    const auto r = write(text);
    EXPECT_EQ(r.status, 2) << message << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  std::filesystem::remove(dir + "/measurements.json");
  ASSERT_EQ(::mkfifo((dir + "/measurements.json").c_str(), 0600), 0);
  const auto fifo = test::run_cli("recommend " + dir);  // refused at once, never blocked on
  EXPECT_EQ(fifo.status, 2);
  EXPECT_NE(fifo.output.find("is a FIFO"), std::string::npos) << fifo.output;
  std::filesystem::remove(dir + "/measurements.json");
  // 64 MiB of text would need about 512 MiB parsed: more than a 400 MiB budget leaves beside the tool
  std::ofstream(dir + "/measurements.json")
      << with("{\"id\": 0,", "{\"id\": 0, \"pad\": \"" + std::string(64 << 20, 'x') + "\",");
  const auto over = test::run_cli("recommend " + dir + " --memory-limit 400M");
  EXPECT_EQ(over.status, 2) << over.output;
  EXPECT_NE(over.output.find("reading measurements.json needs"), std::string::npos) << over.output;
}

TEST(SuiteFilters, TheUsersMapsTechniquesLayersIsasThreadsAndParts) {
  PlanSettings s = suite_settings(true, 2);
  s.heightfields = {parse_heightfield("builtin:waves", 64)};
  s.techniques = {Technique::pom, Technique::cone};
  s.layer_specs = s.few_layer_specs = {parse_layer_spec("16")};
  s.isas = {Isa::scalar};
  s.best_isa = Isa::scalar;
  s.thread_counts = {2};
  s.scale = 0.05f;
  s.window.near_degrees = 45;
  s.window.far_degrees = 85;
  s.parts = kPurposeMatrix | kPurposeGlsl | kPurposeIsa;
  for (const Configuration& c : suite_plan(s)) {
    EXPECT_NE(c.purposes & s.parts, 0u);
    EXPECT_EQ(c.purposes & ~s.parts, 0u) << "purposes left out are stripped";
    EXPECT_EQ(c.params.scale, 0.05f);
    EXPECT_EQ(c.view.near_degrees, 45.0f);
    EXPECT_EQ(c.heightfield.label(), "waves");
    EXPECT_EQ(c.threads, 2);
    if (c.has_technique()) {
      EXPECT_TRUE(c.params.technique == Technique::pom || c.params.technique == Technique::cone);
      if (c.purposes & kPurposeMatrix) {
        EXPECT_EQ(to_string(c.params.layers), "16");
      }
    }
    if (c.on_isa()) {
      EXPECT_EQ(c.isa, Isa::scalar);
    }
  }
  const auto dry = test::run_cli(
      "suite --quick --no-builtins --heightmap builtin:waves --techniques pom --layers 8 "
      "--threads 1 --parts matrix --view-angles 45-85 --scale 0.05 --dry-run");
  ASSERT_EQ(dry.status, 0) << dry.output;
  EXPECT_NE(dry.output.find("waves\ttrace\tpom\t8\t"), std::string::npos) << dry.output;
  EXPECT_NE(dry.output.find("around:45-85 256x256\tbilinear\ttimed\tmatrix\n1 configurations\n"),
            std::string::npos)
      << dry.output;
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"--techniques pom,bogus", "--techniques: bogus not in"},
           {"--isas avx3", "--isas: avx3 not in"},
           {"--parts matrix,everything", "--parts: everything not in"},
           {"--layers 0", "layer"},
           {"--view-angles 80-30", "view angles '80-30' must satisfy 0 <= NEAR < FAR <= 89"},
           {"--scale 2", "--scale: must be in (0, 1], not 2"},
           {"--no-builtins", "--no-builtins requires --heightmap"},
           {"--filter nearest", "--filter: nearest not in"}}) {
    const auto r = test::run_cli("suite --quick --dry-run " + args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
  }
}

// --filter: the run's filter on every configuration that takes one (the kernels, their anchors,
// GLSL), the ports at level 0, the exact reference filterless; a second filter adds the matrix
// under it, timed, for an answer of its own and the report's comparison; claims read one filter.
TEST(SuiteFilters, FilterReadsTheRunAndComparesTheMatrix) {
  PlanSettings s = suite_settings(true, 2);
  s.filter = Filter::trilinear;
  s.compared_filters = {Filter::bilinear};
  std::size_t compared = 0, matrix = 0, held_out[2] = {0, 0};  // by filter: trilinear, bilinear
  const std::vector<Configuration> plan = suite_plan(s);
  for (const Configuration& c : plan) {
    if (c.purposes & kPurposeFilters) {
      ++compared;
      EXPECT_EQ(c.purposes, unsigned(kPurposeFilters));
      EXPECT_EQ(c.params.filter, Filter::bilinear);
      EXPECT_TRUE(c.timed) << "its answer is timed as the run's own";
      // its twin of the matrix, read with the run's filter
      Configuration twin = c;
      twin.params.filter = Filter::trilinear;
      EXPECT_TRUE(std::any_of(plan.begin(), plan.end(), [&](const Configuration& o) {
        return (o.purposes & kPurposeMatrix) && o.same_measurement(twin);
      }));
    } else if (c.purposes == kPurposeHeldOut) {
      held_out[c.params.filter == Filter::bilinear] += 1;  // a candidate's twin reads as its candidate
    } else {
      matrix += (c.purposes & kPurposeMatrix) != 0;
      EXPECT_EQ(c.params.filter, takes_filter(c.kind) ? Filter::trilinear : Filter::bilinear)
          << to_string(c.kind);
    }
  }
  EXPECT_EQ(compared, matrix);
  EXPECT_EQ(held_out[1], compared) << "each compared row has its held-out twin, under its filter";
  EXPECT_GE(held_out[0], matrix);
  const auto dry = test::run_cli(
      "suite --quick --no-builtins --heightmap builtin:waves --techniques pom --layers 8 --threads 1 "
      "--parts matrix,filters --filter trilinear,bilinear --dry-run");
  ASSERT_EQ(dry.status, 0) << dry.output;
  EXPECT_NE(dry.output.find("around 256x256\ttrilinear\ttimed\tmatrix\n"), std::string::npos) << dry.output;
  EXPECT_NE(dry.output.find("around 256x256\tbilinear\ttimed\tfilters\n"), std::string::npos) << dry.output;
  const auto claims =
      test::run_cli("claims --quick --filter bilinear,trilinear --out " + test::temp_dir("claims-filters"));
  EXPECT_EQ(claims.status, 2) << claims.output;
  EXPECT_NE(claims.output.find("claims --filter takes one filter"), std::string::npos) << claims.output;
}

// The default view seen at the user's span of angles: the near edge's centre at NEAR degrees from
// the normal, every ray beyond it; 30-80 is the default view itself, ray for ray.
TEST(SuiteFilters, ViewAnglesPlaceTheDefaultCamera) {
  const auto angles = [](const RayBatch& rays) {
    double lo = 90, hi = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double theta = std::acos(double(rays.vz[i])) * 180.0 / M_PI;
      lo = std::min(lo, theta);
      hi = std::max(hi, theta);
    }
    return std::pair<double, double>{lo, hi};
  };
  const auto [lo, hi] = angles(make_view_rays(parse_view("default:45-85", 64, 64)));
  EXPECT_NEAR(lo, 45.0, 1.0);
  EXPECT_GE(hi, 85.0 - 1.0);
  const RayBatch a = make_view_rays(default_view(64, 64)),
                 b = make_view_rays(parse_view("default:30-80", 64, 64));
  EXPECT_EQ(a.vz, b.vz);
  EXPECT_EQ(a.tx, b.tx);
  EXPECT_EQ(describe(parse_view("default:30-80", 64, 64)), "default 64x64");
  EXPECT_EQ(describe(parse_view("default:45-85", 64, 64)), "default:45-85 64x64");
  for (const char* bad : {"default:80-30", "default:45", "default:-5-30", "default:45-90", "default:a-b"})
    EXPECT_THROW(parse_view(bad, 64, 64), InputError) << bad;
}

}  // namespace
}  // namespace heightmarch
