// The windows a run measures (docs/measures.md#view-sets): the single default view as before, the
// set around the surface, LearnOpenGL's scene, a user's camera poses, their held-out sets and the
// fresh rays of the outside check; and the 95% intervals of the measures over them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include "heightmarch/error.hpp"
#include "heightmarch/metrics.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

std::vector<double> view_angles(const RayBatch& rays) {
  std::vector<double> angles;
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i)) angles.push_back(degrees(std::acos(double(rays.vz[i]))));
  std::sort(angles.begin(), angles.end());
  return angles;
}

double percentile(const std::vector<double>& sorted, double p) {
  return sorted[std::size_t(p / 100.0 * (sorted.size() - 1))];
}

// The share of the rays whose V lies in each of 8 azimuth sectors.
std::vector<double> sector_shares(const RayBatch& rays) {
  std::vector<double> shares(8, 0.0);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (rays.is_padding(i)) continue;
    const double azimuth = degrees(std::atan2(double(rays.vy[i]), double(rays.vx[i]))) + 360.0;
    shares[int(azimuth / 45.0) % 8] += 1.0 / double(rays.ray_count);
  }
  return shares;
}

ViewSpec window(const ViewSet& views, int width, int height) {
  return seen_as(default_view(width, height), views);
}

// LearnOpenGL's parallax scene over one turn sees its quad at 9, 35 and 77 degrees from the normal
// (5th, 50th, 95th percentile), not at the default view's 30 to 80.
TEST(Views, TheTutorialsSceneSeesItsQuadAtItsOwnAngles) {
  const ViewSpec tutorial = window(ViewSet::tutorial(), 200, 150);
  EXPECT_EQ(tutorial.kind, ViewSpec::Kind::tutorial);
  EXPECT_EQ(tutorial.views, kTutorialFrames);
  EXPECT_EQ(describe(tutorial), "tutorial:16 200x150");
  const RayBatch rays = make_view_rays(tutorial);
  const std::vector<double> angles = view_angles(rays);
  EXPECT_NEAR(percentile(angles, 5), 9.0, 1.0);
  EXPECT_NEAR(percentile(angles, 50), 35.0, 1.5);
  EXPECT_NEAR(percentile(angles, 95), 77.0, 1.5);
  // Back faces dropped: about half the turn shows the quad's back, and no ray comes from below.
  EXPECT_GT(rays.ray_count, 0.15 * 200 * 150 * 16);
  EXPECT_LT(rays.ray_count, 0.40 * 200 * 150 * 16);
  for (float tx : rays.tx) EXPECT_TRUE(tx >= 0.0f && tx <= 1.0f);
  EXPECT_EQ(rays.views, std::uint32_t(kTutorialFrames));
}

// A plan's ray budget keeps the tutorial's 800 x 600 window (under trilinear the frame's size sets
// the level of detail) and takes fewer frames of the turn, never more than asked.
TEST(Views, TheTutorialKeepsItsWindowUnderARayBudget) {
  ViewSpec tutorial = window(ViewSet::tutorial(), 1024, 1024);
  size_views_for_rays(tutorial, 1024.0 * 1024.0);
  EXPECT_EQ(tutorial.width, kTutorialWidth);
  EXPECT_EQ(tutorial.height, kTutorialHeight);
  EXPECT_GT(tutorial.views, 1);
  EXPECT_LT(tutorial.views, kTutorialFrames);
  const std::size_t rays = make_view_rays(tutorial).ray_count;
  EXPECT_GT(rays, 0.6 * 1024 * 1024);
  EXPECT_LT(rays, 1.6 * 1024 * 1024);
  ViewSpec three = window(ViewSet::tutorial(3), 64, 64);
  size_views_for_rays(three, 1e8);
  EXPECT_EQ(three.views, 3);
  size_views_for_rays(three, 10.0);
  EXPECT_EQ(three.views, 1);
}

// Subpixel passes: every ray of a pixel moved by the offset, the set's azimuths and offsets kept.
TEST(Views, ASubpixelPassMovesEveryPixelsRayWithinItsPixel) {
  const ViewSpec around = window(ViewSet::around(), 64, 64);
  const RayBatch centre = make_view_rays(around),
                 moved = make_view_rays(subpixel_view(around, 0.25f, -0.25f));
  std::vector<std::size_t> moved_at(std::size_t(64 * 64), centre.size());
  for (std::size_t i = 0; i < moved.size(); ++i)
    if (!moved.is_padding(i)) moved_at[moved.origin[i]] = i;
  double worst = 0;
  std::size_t pairs = 0, differ = 0;
  for (std::size_t i = 0; i < centre.size(); ++i) {
    if (centre.is_padding(i) || moved_at[centre.origin[i]] == centre.size()) continue;
    const std::size_t k = moved_at[centre.origin[i]];
    // A quarter pixel each way: at most about a quarter of the pixel's footprint on each axis,
    // never a jump of azimuth or offset.
    const double du = std::remainder(double(moved.tx[k]) - centre.tx[i], 1.0);
    const double dv = std::remainder(double(moved.ty[k]) - centre.ty[i], 1.0);
    const double step =
        std::hypot(centre.du_dx[i], centre.dv_dx[i]) + std::hypot(centre.du_dy[i], centre.dv_dy[i]);
    worst = std::max(worst, std::hypot(du, dv) / std::max(step, 1e-9));
    ++pairs;
    differ += du != 0.0 || dv != 0.0;
  }
  EXPECT_GT(pairs, centre.ray_count * 9 / 10);
  EXPECT_LT(worst, 0.4);
  EXPECT_EQ(differ, pairs);
}

// Around: the default camera turned about the normal, each tile of its frame from its own azimuth
// at its own offset. Every sector of azimuths gets its share in every band of view angles, the
// frame's angles are the single view's, and the held-out set is another draw.
TEST(Views, AroundTurnsTheDefaultViewToEveryAzimuth) {
  ViewSpec single = window(ViewSet::single(), 512, 512), around = window(ViewSet::around(), 512, 512);
  EXPECT_EQ(describe(single), "default 512x512");
  EXPECT_EQ(describe(around), "around 512x512");
  EXPECT_EQ(describe(held_out_view(around)), "around 512x512 seed 2");
  single.tile_size = around.tile_size = 16;
  EXPECT_FALSE(is_view_set(single));
  EXPECT_TRUE(is_view_set(around));
  const RayBatch one = make_view_rays(single), set = make_view_rays(around),
                 held = make_view_rays(held_out_view(around));
  EXPECT_EQ(set.ray_count, one.ray_count) << "the set traces the frame's pixels once";
  EXPECT_EQ(set.views, std::uint32_t(512 / kViewCell * 512 / kViewCell)) << "a view per cell";
  std::vector<double> a = view_angles(set), b = view_angles(one);
  for (std::size_t i = 0; i < a.size(); i += 97)
    EXPECT_NEAR(a[i], b[i], 1e-3) << "turning keeps every view angle";
  for (const RayBatch* rays : {&set, &held})
    for (double share : sector_shares(*rays)) EXPECT_NEAR(share, 1.0 / 8.0, 0.02);
  // In every band of view angles too: the near rows see every azimuth as the far rows do.
  RayBatch near = set;
  for (std::size_t i = 0; i < near.size(); ++i)
    if (degrees(std::acos(double(near.vz[i]))) > 45.0) near.origin[i] = kPaddingRay;
  near.ray_count =
      std::count_if(near.origin.begin(), near.origin.end(), [](std::uint32_t o) { return o != kPaddingRay; });
  for (double share : sector_shares(near)) EXPECT_NEAR(share, 1.0 / 8.0, 0.03);
  const std::vector<double> single_shares = sector_shares(one);
  EXPECT_GT(single_shares[5] + single_shares[6], 0.95) << "the single view looks from 225-315 degrees";
  // Positions cover the map evenly: each quarter of [0, 1)^2 holds its share.
  double quarter[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < set.size(); ++i)
    if (!set.is_padding(i))
      quarter[(set.tx[i] >= 0.5f) + 2 * (set.ty[i] >= 0.5f)] += 1.0 / double(set.ray_count);
  for (double q : quarter) EXPECT_NEAR(q, 0.25, 0.05);
  // Another draw: no ray of the held-out set is one of the selection set's.
  std::set<std::pair<float, float>> entries;
  for (std::size_t i = 0; i < set.size(); ++i) entries.emplace(set.tx[i], set.vx[i]);
  std::size_t shared = 0;
  for (std::size_t i = 0; i < held.size(); ++i) shared += entries.count({held.tx[i], held.vx[i]});
  EXPECT_LT(shared, held.size() / 1000);
  // Every pixel once, each in its own place of the image.
  std::set<std::uint32_t> pixels;
  for (std::size_t i = 0; i < set.size(); ++i)
    if (!set.is_padding(i)) pixels.insert(set.origin[i]);
  EXPECT_EQ(pixels.size(), set.ray_count);
}

TEST(Views, TheSingleViewIsTodaysRayForRay) {
  const RayBatch a = make_view_rays(default_view(96, 64)),
                 b = make_view_rays(window(ViewSet::single(), 96, 64));
  EXPECT_EQ(a.tx, b.tx);
  EXPECT_EQ(a.vz, b.vz);
  ViewSpec sweep = parse_view("sweep:60,90", 64, 64);
  const RayBatch s = make_view_rays(sweep);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(degrees(std::acos(double(s.vz[i]))), 60.0, 1e-3);
  sweep = seen_as(sweep, ViewSet::around());
  sweep.tile_size = 4;
  EXPECT_EQ(describe(sweep), "sweep:60,90 around 64x64");
  const RayBatch turned = make_view_rays(sweep);
  for (std::size_t i = 0; i < turned.size(); ++i)
    EXPECT_NEAR(degrees(std::acos(double(turned.vz[i]))), 60.0, 1e-3);
  for (double share : sector_shares(turned)) EXPECT_NEAR(share, 1.0 / 8.0, 0.01);
}

TEST(Views, BadWindowsAreRefusedInOneLine) {
  for (const char* bad : {"bogus", "around:8", "tutorial:0", "tutorial:x", "tutorial:99999", "poses"})
    EXPECT_THROW(parse_view_set(bad), InputError) << bad;
  EXPECT_EQ(parse_view_set("tutorial"), ViewSet::tutorial());
  EXPECT_EQ(parse_view_set("tutorial:3"), ViewSet::tutorial(3));
  EXPECT_EQ(parse_view_set("around"), ViewSet::around());
  EXPECT_EQ(parse_view_set("cam.csv"), ViewSet::poses("cam.csv"));
  // The typed values are checked too: a sweep has no tutorial's scene, a scene has 1 to 4096 frames.
  const ViewSpec sweep = parse_view("sweep:30", 64, 64);
  EXPECT_THROW(seen_as(sweep, ViewSet::tutorial()), InputError);
  EXPECT_THROW(seen_as(sweep, ViewSet::poses("cam.csv")), InputError);
  EXPECT_THROW(seen_as(default_view(64, 64), ViewSet::tutorial(0)), InputError);
  EXPECT_THROW(seen_as(rays_file_view("rays.csv"), ViewSet::around()), InputError);
}

// A user's camera: the surface is the plane z = 0 with uv = (x, y), repeating.
TEST(Views, CameraPosesFromACsv) {
  const std::string dir = test::temp_dir("poses");
  const std::string header = "eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,fov,width,height\n";
  std::ofstream(dir + "/down.csv") << header << "0.5,0.5,2,0.5,0.5,0,0,1,0,20,64,48\n"
                                   << "0,-3,1, 0,0,0, 0,0,1, 60, 80,60\n";
  const ViewSpec view = seen_as(default_view(1, 1), ViewSet::poses(dir + "/down.csv"));
  EXPECT_EQ(view.kind, ViewSpec::Kind::poses);
  const RayBatch rays = make_view_rays(view);
  EXPECT_EQ(rays.views, 2u);
  // Straight down from 2 units with a 20 degree field of view (26 across at 4:3): every pixel sees
  // the plane, the corners at about 16 degrees from the normal.
  std::size_t first_pose = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i) && rays.view[i] == 0) {
      ++first_pose;
      EXPECT_LT(degrees(std::acos(double(rays.vz[i]))), 17.0);
    }
  EXPECT_EQ(first_pose, 64u * 48u);
  // The second pose looks towards the horizon: the sky misses, the plane up to 89 degrees is kept.
  const std::vector<double> angles = view_angles(rays);
  EXPECT_LE(angles.back(), kMaxViewDegrees + 1e-3);
  for (float t : rays.tx) EXPECT_TRUE(t >= 0.0f && t < 1.0f);
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"eye_x,eye_y\n1,2\n", "header must be"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,20,64\n", ":2: expected 12 columns, found 11"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,20,64,x\n", ":2: height 'x' is not a number"},
      {header + "0.5,0.5,-1,0.5,0.5,0,0,1,0,20,64,48\n", ":2: the eye must be above the surface"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,0,1,20,64,48\n", ":2: up is zero or along the view direction"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,180,64,48\n", ":2: fov must be in (0, 180) degrees"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,20,0,48\n", ":2: width must be a whole number of pixels"},
      {header, "no camera poses"},
      {header + "0,0,1,0,1,2,0,0,1,20,8,8\n", "no pose sees the surface"},
      // Each field in range, but the rays meet the plane beyond a float's range: T infinite, the
      // gradients and the wrap NaN, which crashed every tool that traced them. The one check of
      // every batch names the pose and its line.
      {header + "3e38,3e38,3e38,-3e38,-3e38,0,0,0,1,170,8,8\n",
       "bad.csv:2: pose 1: its entry point T is not finite: its rays cannot be traced"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,20,8,8\n\n3e38,3e38,3e38,-3e38,-3e38,0,0,0,1,170,8,8\n",
       "bad.csv:4: pose 2: its entry point T is not finite"},
      // Far enough out that T wraps to a float, but a pixel spans more than 1e6 repeats of the map.
      {header + "1e9,1e9,1e9,0,0,0,0,0,1,90,8,8\n",
       "pose 1: its pixel footprint (the gradients of T) is not finite or beyond 1e6"},
      {header + "0.5,0.5,2,0.5,0.5,0,0,1,0,20,64,48" + std::string(5000, ' ') + "\n",
       ":2: a line longer than 4096 bytes"}};
  for (const auto& [text, message] : bad) {
    std::ofstream(dir + "/bad.csv") << text;
    const ViewSpec v = seen_as(default_view(1, 1), ViewSet::poses(dir + "/bad.csv"));
    try {
      make_view_rays(v);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

// The outside check's rays: every azimuth and position uniform, the view angles the window's.
TEST(Views, FreshRaysHaveTheWindowsAnglesAndEveryAzimuth) {
  ViewSpec fresh = window(ViewSet::single(), 128, 128);
  fresh.fresh_rays = 40000;
  fresh.seed = 7;
  EXPECT_EQ(describe(fresh), "fresh 40000 rays like default 128x128 seed 7");
  const RayBatch rays = make_view_rays(fresh);
  EXPECT_EQ(rays.ray_count, 40000u);
  const std::vector<double> drawn = view_angles(rays),
                            own = view_angles(make_view_rays(window(ViewSet::single(), 128, 128)));
  for (double p : {5.0, 50.0, 95.0}) EXPECT_NEAR(percentile(drawn, p), percentile(own, p), 1.0) << p;
  for (double share : sector_shares(rays)) EXPECT_NEAR(share, 1.0 / 8.0, 0.01);
  // Each has the footprint of the window's ray it takes its angle from, turned with its azimuth: the
  // same size (its level of detail, its pixels), and the window's spread of sizes.
  const auto sizes = [](const RayBatch& batch) {
    std::vector<double> area;
    for (std::size_t i = 0; i < batch.size(); ++i)
      if (!batch.is_padding(i))
        area.push_back(
            std::fabs(double(batch.du_dx[i]) * batch.dv_dy[i] - double(batch.du_dy[i]) * batch.dv_dx[i]));
    std::sort(area.begin(), area.end());
    return area;
  };
  const std::vector<double> fresh_area = sizes(rays),
                            own_area = sizes(make_view_rays(window(ViewSet::single(), 128, 128)));
  // The areas come in steps (a view's rows share theirs): each percentile of the drawn ones lies
  // within a percent of ranks of the window's.
  for (double p : {5.0, 50.0, 95.0}) {
    EXPECT_GE(percentile(fresh_area, p), percentile(own_area, p - 1.0)) << "footprint area, p" << p;
    EXPECT_LE(percentile(fresh_area, p), percentile(own_area, p + 1.0)) << "footprint area, p" << p;
  }
  EXPECT_GT(percentile(fresh_area, 5.0), 0.0) << "every fresh ray has a footprint";
}

// Clopper-Pearson and the order statistics' interval against known values (R's binom.test and the
// normal approximation far from the tails).
TEST(Confidence, IntervalsOfARateAndAPercentile) {
  const Interval a = clopper_pearson(5, 100);
  EXPECT_NEAR(a.low, 0.01643, 1e-4);
  EXPECT_NEAR(a.high, 0.11284, 1e-4);
  const Interval none = clopper_pearson(0, 1000);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.003682, 1e-5);
  EXPECT_NEAR(incomplete_beta(2, 3, 0.4), 0.5248, 1e-4);
  const double n = 1e6, p = 0.99;
  const Interval ranks = quantile_rank_interval(p, n);
  const double half = 1.96 * std::sqrt(p * (1 - p) / n);
  EXPECT_NEAR(ranks.low, p - half, 2e-5);
  EXPECT_NEAR(ranks.high, p + half, 2e-5);
}

// Over independent rays the intervals are the plain ones; over a view set, whose rays err in
// clusters, they widen, and they always hold the figure.
TEST(Confidence, SummariesCarryIntervalsThatHoldTheirFigures) {
  const RayBatch rays = test::random_rays(20000, 80.0, 3);
  HitBuffers hits, exact;
  hits.resize(rays.size());
  exact.resize(rays.size());
  test::Random rng(5);
  for (std::size_t i = 0; i < rays.size(); ++i)
    hits.u[i] = float(rng.uniform() < 0.01 ? 4.0 : 0.1 * rng.uniform()) / 64.0f;
  const ErrorSummary summary = summarize_errors(rays, hits, {exact, exact}, 64, 64, Writes::hit);
  const ErrorDistribution& e = summary.uv;
  EXPECT_NEAR(e.effective_rays, double(e.rays), 0.35 * e.rays) << "independent rays: about no design effect";
  const Interval cp = clopper_pearson(e.wrong_rate * e.effective_rays, e.effective_rays);
  EXPECT_NEAR(e.wrong_ci.low, cp.low, 1e-9);
  for (const auto& [value, ci] :
       {std::pair{e.p50, e.p50_ci}, {e.p95, e.p95_ci}, {e.p99, e.p99_ci}, {e.wrong_rate, e.wrong_ci}}) {
    EXPECT_LE(ci.low, value);
    EXPECT_GE(ci.high, value);
    EXPECT_LT(ci.low, ci.high);
  }
  EXPECT_FALSE(e.by_azimuth.empty());
  std::size_t grouped = 0;
  for (const ErrorGroup& g : e.by_azimuth) grouped += g.rays;
  EXPECT_EQ(grouped, e.rays);
  EXPECT_FALSE(summary.pixels.measured) << "a list of rays has no pixel grid";
}

// A ray's pixel error is its uv error in its pixel's own axes: through the inverse of its
// footprint, stretched or turned.
TEST(PixelError, ThroughTheInverseOfTheFootprint) {
  // One pixel is 1/64 in u and 1/32 in v: 1/64 in u is one pixel, 1/16 in v two.
  EXPECT_NEAR(pixel_offset(1.0 / 64, 0.0, 1.0 / 64, 0.0, 0.0, 1.0 / 32), 1.0, 1e-12);
  EXPECT_NEAR(pixel_offset(0.0, 1.0 / 16, 1.0 / 64, 0.0, 0.0, 1.0 / 32), 2.0, 1e-12);
  // The footprint turned by 30 degrees and the offset with it: the same lengths.
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6), a = 1.0 / 64, b = 1.0 / 32;
  EXPECT_NEAR(pixel_offset(c * 3 * a, s * 3 * a, c * a, s * a, -s * b, c * b), 3.0, 1e-9);
  EXPECT_NEAR(pixel_offset(-s * 5 * b, c * 5 * b, c * a, s * a, -s * b, c * b), 5.0, 1e-9);
  // A sheared footprint (a grazing view): x moves u, y moves u and v.
  EXPECT_NEAR(pixel_offset(0.0, 0.01, 0.01, 0.0, 0.04, 0.01), std::hypot(-4.0, 1.0), 1e-9);
  EXPECT_TRUE(std::isnan(pixel_offset(0.01, 0.0, 0.0, 0.0, 0.0, 0.0))) << "no footprint, no pixels";
  EXPECT_TRUE(std::isnan(pixel_offset(0.01, 0.0, 0.01, 0.01, 0.02, 0.02))) << "a footprint of no area";
}

// The distributions of a summary: the hit against level 0 and against the surface read, and the
// surface read's from level 0, in texels and pixels; a wrong pixel is one more than a pixel off.
TEST(PixelError, SearchErrorAndFilterBiasApart) {
  RayBatch rays = test::random_rays(4000, 60.0, 9);
  for (std::size_t i = 0; i < rays.size(); ++i) {  // two pixels a texel on a 64 x 64 map
    rays.du_dx[i] = 1.0f / 128;
    rays.dv_dy[i] = 1.0f / 128;
  }
  HitBuffers hits, level0, read;
  for (HitBuffers* h : {&hits, &level0, &read}) h->resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    read.u[i] = 2.0f / 64;  // the surface read's hit 2 texels (4 pixels) from level 0's
    hits.u[i] = read.u[i] + (i % 4 == 0 ? 0.75f : 0.25f) / 64;  // the search 0.25 or 0.75 texel off it
  }
  const ErrorSummary e = summarize_errors(rays, hits, {level0, read}, 64, 64, Writes::hit);
  ASSERT_TRUE(e.pixels.measured && e.search_pixels.measured && e.bias_pixels.measured);
  EXPECT_NEAR(e.search.max, 0.75, 1e-6);
  EXPECT_NEAR(e.search.p50, 0.25, 1e-6);
  EXPECT_NEAR(e.search_pixels.max, 1.5, 1e-5);
  EXPECT_NEAR(e.search.wrong_rate, 0.0, 1e-12) << "no search is more than a texel off";
  EXPECT_NEAR(e.search_pixels.wrong_rate, 0.25, 0.01) << "a quarter of the rays more than a pixel off";
  EXPECT_NEAR(e.bias.p99, 2.0, 1e-6);
  EXPECT_NEAR(e.bias_pixels.p99, 4.0, 1e-5);
  EXPECT_NEAR(e.bias.wrong_rate, 1.0, 1e-12);
  EXPECT_NEAR(e.uv.max, 2.75, 1e-6) << "against level 0, the two added";
  EXPECT_NEAR(e.pixels.max, 5.5, 1e-5);
  EXPECT_EQ(e.uv.by_azimuth.size(), e.pixels.by_azimuth.size());
  EXPECT_TRUE(e.search.by_azimuth.empty()) << "only the errors against level 0 are broken down";
  // Every measure of the list has its value, under its name.
  const auto measures = error_measures(e);
  ASSERT_EQ(measures.size(), error_measure_list().size());
  for (std::size_t k = 0; k < measures.size(); ++k)
    EXPECT_EQ(measures[k].first, error_measure_list()[k].name);
  const auto find = [&](const std::string& name) {
    for (const auto& [n, v] : measures)
      if (n == name) return v;
    return -1.0;
  };
  EXPECT_NEAR(find("search_pixel_error_max"), 1.5, 1e-5);
  EXPECT_NEAR(find("wrong_pixel_rate"), 1.0, 1e-12);
  EXPECT_NEAR(find("filter_wrong_surface_rate"), 1.0, 1e-12);
}

}  // namespace
}  // namespace heightmarch
