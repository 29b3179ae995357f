// The shaded image (docs/measures.md#the-shaded-image): shading, the colour difference, and the
// image error of techniques against the exact reference supersampled.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include "experiment/plan_runner.hpp"
#include "experiment/suite_plan.hpp"
#include "heightmarch/error.hpp"
#include "io/colour_difference.hpp"
#include "io/images.hpp"
#include "io/shading.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

LinearImage flat_image(int width, int height, float r, float g, float b) {
  LinearImage image{width, height, {}};
  for (int p = 0; p < width * height; ++p) image.rgb.insert(image.rgb.end(), {r, g, b});
  return image;
}

TEST(ColourDifference, IsZeroOnIdenticalImagesAndAHundredFromBlackToWhite) {
  const LinearImage grey = flat_image(5, 3, 0.2f, 0.3f, 0.4f), black = flat_image(5, 3, 0, 0, 0),
                    white = flat_image(5, 3, 1, 1, 1);
  for (float d : ciede2000(grey, grey)) EXPECT_NEAR(d, 0.0f, 1e-4f);
  // L* 0 to 100 at a mean lightness of 50: S_L = 1, no chroma, so Delta E00 = Delta L* = 100.
  for (float d : ciede2000(black, white)) EXPECT_NEAR(d, 100.0f, 0.05f);
}

TEST(ColourDifference, ADifferenceJustAboveVisibleIsCountedAndTheMeanAndP99AreThePixels) {
  std::vector<float> delta_e = {0.5f, 1.0f, 2.5f, 3.0f, 9.0f, 100.0f};
  std::vector<std::uint8_t> compared = {1, 1, 1, 1, 1, 0};
  const ImageError e = summarize_image_error(delta_e, compared);
  EXPECT_EQ(e.pixels, 5u);
  EXPECT_NEAR(e.mean, (0.5 + 1.0 + 2.5 + 3.0 + 9.0) / 5.0, 1e-9);
  EXPECT_DOUBLE_EQ(e.p99, 9.0);
  EXPECT_DOUBLE_EQ(e.visible_share, 3.0 / 5.0);
}

TEST(Shading, SrgbRoundTripsAndItsEndsAreFixed) {
  for (float x = 0.0f; x <= 1.0f; x += 1.0f / 64.0f) EXPECT_NEAR(srgb_decode(srgb_encode(x)), x, 2e-6f);
  EXPECT_EQ(srgb_encode(0.0f), 0.0f);
  EXPECT_NEAR(srgb_encode(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(srgb_encode(0.214041f), 0.5f, 1e-4f);  // mid-grey's linear value
}

// The procedural albedo: sand at depth 0 on a light square, 40% of it at depth 1, 70% on the
// board's dark squares.
TEST(Shading, ProceduralAlbedoIsSandDarkenedByDepthOnACheckerboard) {
  DepthMap map{16, 16, std::vector<float>(256, 0.0f)};
  map.texels[0] = 1.0f;  // texel (0, 0): square (0, 0), light, deepest
  const Albedo albedo = procedural_albedo(map);
  const float sand_r = srgb_decode(217.0f / 255.0f);
  const DepthMap& red = albedo.chains[0][0];
  EXPECT_NEAR(red.at(1, 0), sand_r, 1e-6f);         // light square, top
  EXPECT_NEAR(red.at(0, 0), 0.4f * sand_r, 1e-6f);  // light square, deepest
  EXPECT_NEAR(red.at(2, 0), 0.7f * sand_r, 1e-6f);  // square (1, 0), dark
  EXPECT_EQ(albedo.chains[0].size(), 5u);           // 16, 8, 4, 2, 1
}

// A lit flat plane: the albedo times (ambient + (1 - ambient) N.L), N = +z.
TEST(Shading, AFlatPlaneUnderTheLightIsItsAlbedoLit) {
  DepthMap map{64, 64, std::vector<float>(64 * 64, 0.0f)};
  const Albedo albedo = procedural_albedo(map);
  Shading s;
  s.map = &map;
  s.albedo = &albedo;
  s.light = {0.6f, 0.0f, 0.8f};
  const float u = 3.5f / 64.0f;  // texel (3, 3)'s centre, on the board's first (light) square
  const std::array<float, 3> c = shade(s, u, u, 1.0f, 0, 0, 0, 0);
  EXPECT_NEAR(c[1], srgb_decode(158.0f / 255.0f) * (kAmbient + (1.0f - kAmbient) * 0.8f), 1e-6f);
  // In full shadow the light's direct part goes.
  EXPECT_NEAR(shade(s, u, u, 0.0f, 0, 0, 0, 0)[1], srgb_decode(158.0f / 255.0f) * kAmbient, 1e-6f);
}

// A user's colour texture: an 8-bit PNG is sRGB, decoded to linear light.
TEST(Shading, AnAlbedoFileIsReadInLinearLight) {
  const std::string dir = test::temp_dir("albedo");
  const std::string path = dir + "/colour.png";
  write_rgb8(path, 2, 2, std::vector<std::uint8_t>(12, 128));
  const Albedo albedo = load_albedo(path);
  EXPECT_EQ(albedo.source, path);
  EXPECT_NEAR(albedo.chains[2][0].at(1, 1), srgb_decode(128.0f / 255.0f), 1e-6f);
  EXPECT_THROW(load_albedo(dir + "/missing.png"), InputError);
}

// A gallery-like row on a builtin: its image error at n x n = 4 x 4 against the exact reference.
Configuration gallery_row(const std::string& builtin, RunKind kind, Technique technique, const char* layers) {
  Configuration c;
  c.kind = kind;
  c.heightfield = parse_heightfield("builtin:" + builtin, 256);
  c.view = default_view(192, 144);
  c.params.technique = technique;
  c.params.layers = layers_for(technique, parse_layer_spec(layers));
  c.isa = best_isa();
  c.threads = 0;
  c.timed = false;
  c.purposes = kPurposeGallery;
  c.supersample = 4;
  return c;
}

double mean_image_error(const Measurement& m) {
  EXPECT_TRUE(m.image_error.has_value()) << m.config.label();
  return m.image_error ? m.image_error->mean : 0.0;
}

// On every builtin of the suite: the exact render at one ray a pixel against its own 4 x 4 is the
// resolve's floor; maxmip reads as the exact within it (its mean difference within 2% of the
// exact's, and its visible share within half a point), and steep and POM read worse at 8 layers
// than at 32 (mean and visible share).
TEST(ImageError, MaxmipReadsAsExactAndFewLayersReadWorse) {
  for (const char* builtin : {"bricks", "toybox", "terrain", "waves", "spikes"}) {
    SCOPED_TRACE(builtin);
    std::vector<Configuration> plan = {gallery_row(builtin, RunKind::exact, Technique::pom, "32"),
                                       gallery_row(builtin, RunKind::trace, Technique::maxmip, "1")};
    for (Technique t : {Technique::steep, Technique::pom})
      for (const char* layers : {"8", "32"}) plan.push_back(gallery_row(builtin, RunKind::trace, t, layers));
    MeasureOptions options;
    options.repetitions = 1;
    const MeasuredPlan run = measure_plan(plan, options);
    const Measurement &exact = run.rows[0], &maxmip = run.rows[1];
    const double floor = mean_image_error(exact);
    EXPECT_GT(floor, 0.0);
    EXPECT_LE(std::fabs(mean_image_error(maxmip) - floor), 0.02 * floor);
    EXPECT_LE(std::fabs(maxmip.image_error->visible_share - exact.image_error->visible_share), 0.005);
    for (std::size_t k = 2; k < run.rows.size(); k += 2) {
      const Measurement &few = run.rows[k], &many = run.rows[k + 1];
      SCOPED_TRACE(few.config.label());
      EXPECT_GT(mean_image_error(few), mean_image_error(many));
      EXPECT_GT(few.image_error->visible_share, many.image_error->visible_share);
    }
  }
}

// The gallery shows what the run measured: its window as a picture (the tutorial's scene, a
// user's poses) and each technique at the layer counts asked, every row's image compared.
TEST(Gallery, ShowsTheRunsWindowAndTheLayersAsked) {
  PlanSettings s = suite_settings(true, 1);
  PlanFilters asked;
  asked.techniques = {"steep", "pom", "maxmip"};
  asked.layers = {"8", "16"};
  asked.parts = {"gallery"};
  apply(asked, s);
  const auto gallery_rows = [&] {
    std::vector<Configuration> rows;
    for (const Configuration& c : suite_plan(s))
      if (c.purposes & kPurposeGallery) rows.push_back(c);
    return rows;
  };
  s.window = seen_as(default_view(kTutorialWidth, kTutorialHeight), ViewSet::tutorial());
  std::set<std::string> steep, pom;
  for (const Configuration& c : gallery_rows()) {
    EXPECT_EQ(c.view.kind, ViewSpec::Kind::tutorial);
    EXPECT_EQ(c.view.views, kGalleryTutorialFrames);
    EXPECT_EQ(c.view.width, kTutorialWidth / 2);
    EXPECT_EQ(c.supersample, kGallerySupersample);
    if (c.kind == RunKind::trace && c.params.technique == Technique::steep)
      steep.insert(to_string(c.params.layers));
    if (c.kind == RunKind::trace && c.params.technique == Technique::pom)
      pom.insert(to_string(c.params.layers));
  }
  EXPECT_EQ(steep, (std::set<std::string>{"8", "16"}));
  EXPECT_EQ(pom, (std::set<std::string>{"8", "16", "32"}));  // and the tutorial's comparison at 32
  const std::string poses = test::temp_dir("gallery-poses") + "/poses.csv";
  std::ofstream(poses) << "eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,fov,width,height\n"
                       << "0.5,-1,1,0.5,2,0,0,0,1,60,64,48\n";
  s.window = seen_as(default_view(64, 64), ViewSet::poses(poses));
  for (const Configuration& c : gallery_rows()) {
    EXPECT_EQ(c.view.kind, ViewSpec::Kind::poses);
    EXPECT_EQ(c.view.path, poses);
  }
}

}  // namespace
}  // namespace heightmarch
