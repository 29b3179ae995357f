// Builtin heightfields and depth maps from image files: formats, conventions and hostile files.
#include "heightmarch/heightfield.hpp"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "heightmarch/error.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

void write_image(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type,
                 const std::vector<float>& pixels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << path;
  OIIO::ImageSpec spec(w, h, channels, type);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the pixels are written as given, alpha apart
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  out->close();
}

TEST(Builtins, DeterministicFiniteInRangeAtAnySize) {
  for (const std::string& name : builtin_heightfield_names())
    for (int res : {1, 2, 3, 17, 128}) {
      const DepthMap a = make_builtin_heightfield(name, res, 5), b = make_builtin_heightfield(name, res, 5);
      ASSERT_EQ(a.width, res);
      ASSERT_EQ(a.texels, b.texels) << name << " " << res;
      for (float d : a.texels) ASSERT_TRUE(d >= 0.0f && d <= 1.0f) << name << " " << res;
    }
}

TEST(Builtins, SeedChangesTheRandomOnes) {
  for (const char* name : {"waves", "terrain", "bricks", "toybox", "spikes"})
    EXPECT_NE(make_builtin_heightfield(name, 64, 1).texels, make_builtin_heightfield(name, 64, 2).texels)
        << name;
  EXPECT_EQ(make_builtin_heightfield("ramp", 64, 1).texels, make_builtin_heightfield("ramp", 64, 2).texels);
}

TEST(Builtins, BadNameAndResolution) {
  EXPECT_THROW(make_builtin_heightfield("nope", 64, 1), InputError);
  EXPECT_THROW(make_builtin_heightfield("bricks", 0, 1), InputError);
  EXPECT_THROW(make_builtin_heightfield("bricks", 100000, 1), InputError);
}

TEST(Loading, FormatsDepthsAndChannels) {
  const std::string dir = test::temp_dir("formats");
  const std::vector<float> gray = {0.0f, 0.25f, 0.5f, 1.0f, 0.75f, 0.125f};  // 3 x 2
  std::vector<float> rgba;
  for (float g : gray) rgba.insert(rgba.end(), {g, 0.9f, 0.1f, 1.0f});
  std::vector<float> two;
  for (float g : gray) two.insert(two.end(), {g, 0.5f});
  struct Case {
    std::string file;
    int channels;
    OIIO::TypeDesc type;
    const std::vector<float>* pixels;
    float tolerance;
  };
  const std::vector<Case> cases = {{"a.png", 1, OIIO::TypeDesc::UINT8, &gray, 1.0f / 255},
                                   {"b.png", 4, OIIO::TypeDesc::UINT8, &rgba, 1.0f / 255},
                                   {"c.png", 1, OIIO::TypeDesc::UINT16, &gray, 1.0f / 65535},
                                   {"d.exr", 2, OIIO::TypeDesc::FLOAT, &two, 0.0f},
                                   {"e.tif", 4, OIIO::TypeDesc::UINT16, &rgba, 1.0f / 65535},
                                   {"f.tif", 1, OIIO::TypeDesc::FLOAT, &gray, 0.0f}};
  for (const Case& c : cases) {
    write_image(dir + "/" + c.file, 3, 2, c.channels, c.type, *c.pixels);
    const DepthMap depth = load_depth_map(dir + "/" + c.file);
    ASSERT_EQ(depth.width, 3) << c.file;
    ASSERT_EQ(depth.height, 2) << c.file;
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(depth.texels[k], gray[k], c.tolerance + 1e-6f) << c.file << " texel " << k;
    const DepthMap height = load_depth_map(dir + "/" + c.file, {Convention::height});
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(height.texels[k], 1.0f - depth.texels[k], 1e-6f) << c.file;
  }
}

// The depth is the first channel as stored, never multiplied by alpha (what GLSL's .r reads).
TEST(Loading, AlphaNeverScalesTheDepth) {
  const std::string dir = test::temp_dir("alpha");
  const std::vector<float> gray = {0.0f, 0.25f, 0.5f, 1.0f, 0.75f, 0.125f};
  const std::vector<float> alpha = {0.0f, 0.5f, 1.0f, 0.0f, 0.2f, 0.9f};
  std::vector<float> rgba, ga;
  for (int k = 0; k < 6; ++k) {
    rgba.insert(rgba.end(), {gray[k], 0.3f, 0.6f, alpha[k]});
    ga.insert(ga.end(), {gray[k], alpha[k]});
  }
  write_image(dir + "/rgba.png", 3, 2, 4, OIIO::TypeDesc::UINT8, rgba);
  write_image(dir + "/ga.png", 3, 2, 2, OIIO::TypeDesc::UINT8, ga);
  for (const char* file : {"rgba.png", "ga.png"}) {
    const DepthMap depth = load_depth_map(dir + "/" + file);
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(depth.texels[k], gray[k], 1.0f / 255 + 1e-6f) << file << " texel " << k;
  }
}

TEST(Loading, HandWrittenPfm) {
  const std::string dir = test::temp_dir("pfm");
  const float texels[2] = {0.0f, 1.0f};
  std::ofstream(dir + "/row.pfm", std::ios::binary)
      << "Pf\n2 1\n-1.0\n"
      << std::string(reinterpret_cast<const char*>(texels), sizeof texels);
  const DepthMap map = load_depth_map(dir + "/row.pfm");
  EXPECT_EQ(map.texels, (std::vector<float>{0.0f, 1.0f}));
}

TEST(Loading, RowZeroIsVZero) {
  const std::string dir = test::temp_dir("rows");
  write_image(dir + "/rows.exr", 1, 2, 1, OIIO::TypeDesc::FLOAT, {0.2f, 0.8f});
  const DepthMap map = load_depth_map(dir + "/rows.exr");
  EXPECT_FLOAT_EQ(map.at(0, 0), 0.2f);
  EXPECT_FLOAT_EQ(map.at(0, 1), 0.8f);
}

TEST(Loading, OutOfRangeValuesAreClamped) {
  const std::string dir = test::temp_dir("range");
  write_image(dir + "/range.exr", 2, 1, 1, OIIO::TypeDesc::FLOAT, {-0.5f, 3.0f});
  const DepthMap map = load_depth_map(dir + "/range.exr");
  EXPECT_EQ(map.texels, (std::vector<float>{0.0f, 1.0f}));
}

TEST(Loading, HostileFilesAreInputErrors) {
  const std::string dir = test::temp_dir("hostile");
  write_image(dir + "/nan.exr", 2, 2, 1, OIIO::TypeDesc::FLOAT, {0.1f, NAN, 0.2f, INFINITY});
  std::ofstream(dir + "/empty.png");
  std::ofstream(dir + "/text.png") << "not an image";
  std::ofstream(dir + "/magic.png", std::ios::binary) << std::string("\x89PNG\r\n\x1a\nGARBAGEGARBAGE", 22);
  // A PFM header claiming 100000 x 100000 float pixels, with none behind it.
  std::ofstream(dir + "/huge.pfm", std::ios::binary) << "Pf\n100000 100000\n-1.0\n";
  std::ofstream(dir + "/zero.pfm", std::ios::binary) << "Pf\n0 0\n-1.0\n";
  // Truncated pixel data: a 64 x 64 PFM with 10 bytes of pixels.
  std::ofstream(dir + "/truncated.pfm", std::ios::binary) << "Pf\n64 64\n-1.0\n0123456789";
  for (const char* file : {"nan.exr", "empty.png", "text.png", "magic.png", "huge.pfm", "zero.pfm",
                           "truncated.pfm", "missing.png"}) {
    try {
      load_depth_map(dir + "/" + file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  try {
    load_depth_map(dir + "/nan.exr");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 NaN/Inf texels (first at 1,0)"), std::string::npos) << e.what();
  }
}

TEST(Loading, FirstSubimageOfAMultiImageFile) {
  const std::string dir = test::temp_dir("multi");
  const std::string path = dir + "/multi.tif";
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->supports("multiimage"));
  const OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::FLOAT),
                                    OIIO::ImageSpec(3, 3, 1, OIIO::TypeDesc::FLOAT)};
  ASSERT_TRUE(out->open(path, 2, specs));
  const float first[2] = {0.3f, 0.6f};
  const float second[9] = {};
  out->write_image(OIIO::TypeDesc::FLOAT, first);
  out->open(path, specs[1], OIIO::ImageOutput::AppendSubimage);
  out->write_image(OIIO::TypeDesc::FLOAT, second);
  out->close();
  const DepthMap map = load_depth_map(path);
  EXPECT_EQ(map.width, 2);
  EXPECT_FLOAT_EQ(map.texels[1], 0.6f);
}

// A normal map in RGB (a constant 0.5 on a flat normal) with the depth in alpha: reading R, the
// default, would measure a flat map; it is refused naming the channel that varies. The depth
// read from alpha, a flat map allowed on purpose, and a map constant in every channel all load.
TEST(Loading, AConstantChannelWhileAnotherVariesIsRefused) {
  const std::string dir = test::temp_dir("flat-channel");
  const std::vector<float> depth = {0.0f, 0.25f, 0.5f, 1.0f, 0.75f, 0.125f};
  std::vector<float> normal_and_depth, constant;
  for (float d : depth) {
    normal_and_depth.insert(normal_and_depth.end(), {0.5f, 0.5f, 1.0f, d});
    constant.insert(constant.end(), {0.5f, 0.5f, 1.0f, 1.0f});
  }
  write_image(dir + "/rgba.png", 3, 2, 4, OIIO::TypeDesc::UINT8, normal_and_depth);
  write_image(dir + "/flat.png", 3, 2, 4, OIIO::TypeDesc::UINT8, constant);
  write_image(dir + "/grey.png", 3, 2, 1, OIIO::TypeDesc::UINT8, std::vector<float>(6, 0.5f));
  try {
    load_depth_map(dir + "/rgba.png");
    ADD_FAILURE() << "a constant red channel beside a varying alpha was read as the depth";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("rgba.png: channel 0 (R), read as the depth, is constant (0.501961) while "
                                   "channel 3 (A) varies: choose the depth's channel with --channel 3"),
        std::string::npos)
        << e.what();
  }
  MapReading alpha;
  alpha.channel = 3;
  const DepthMap read = load_depth_map(dir + "/rgba.png", alpha);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(read.texels[k], depth[k], 1.0f / 255 + 1e-6f) << k;
  MapReading flat;
  flat.allow_flat = true;
  EXPECT_EQ(load_depth_map(dir + "/rgba.png", flat).texels, std::vector<float>(6, 128.0f / 255));
  EXPECT_EQ(load_depth_map(dir + "/flat.png").texels, std::vector<float>(6, 128.0f / 255));
  EXPECT_EQ(load_depth_map(dir + "/grey.png").texels, std::vector<float>(6, 128.0f / 255));
}

// A map list's entry carries its own reading, typed, and describe() writes it back as it is read.
TEST(MapEntries, OptionsOfAnEntryOverrideTheCommandsReading) {
  const std::string dir = test::temp_dir("entries");
  write_image(dir + "/rock.png", 2, 2, 4, OIIO::TypeDesc::UINT8, std::vector<float>(16, 0.5f));
  MapReading defaults;
  defaults.convention = Convention::height;
  const HeightfieldSource plain = parse_heightfield(dir + "/rock.png", 512, 1, defaults);
  EXPECT_EQ(plain.reading, defaults);
  const HeightfieldSource own =
      parse_heightfield(dir + "/rock.png:wrap=clamp:channel=a:convention=depth", 512, 1, defaults);
  EXPECT_EQ(own.path, dir + "/rock.png");
  EXPECT_EQ(own.reading.convention, Convention::depth);
  EXPECT_EQ(own.reading.channel, 3);
  EXPECT_EQ(own.reading.wrap, Wrap::clamp);
  EXPECT_EQ(own.describe(), dir + "/rock.png:channel=3:wrap=clamp");
  EXPECT_EQ(parse_heightfield(own.describe()), own);
  EXPECT_EQ(parse_heightfield("builtin:waves:wrap=clamp").reading.wrap, Wrap::clamp);
  // A file whose own name ends like an option is that file.
  std::ofstream(dir + "/odd:wrap=clamp") << "a file of that name";
  EXPECT_EQ(parse_heightfield(dir + "/odd:wrap=clamp").path, dir + "/odd:wrap=clamp");
  // Its colour texture, an existing file.
  std::ofstream(dir + "/colour.png") << "a colour texture";
  EXPECT_EQ(parse_heightfield("builtin:waves:albedo=" + dir + "/colour.png").albedo, dir + "/colour.png");
  for (const auto& [entry, message] : std::vector<std::pair<std::string, std::string>>{
           {dir + "/rock.png:chanel=a", "unknown option 'chanel' (convention, channel, wrap, albedo)"},
           {dir + "/rock.png:wrap=clamp:wrap=repeat", "wrap given twice"},
           {dir + "/rock.png:wrap=mirror", "rock.png:wrap=mirror: wrap 'mirror': repeat or clamp"},
           {dir + "/rock.png:convention=up", "depth (white = deep) or height (white = high)"},
           {dir + "/rock.png:channel=x", "a channel index from 0, or r, g, b, a"},
           {"builtin:bricks:channel=1", "applies to a depth map file, not builtin:bricks"},
           {"builtin:bricks:convention=height", "applies to a depth map file, not builtin:bricks"},
           {"builtin:bricks:albedo=" + dir + "/none.png", "none.png': no such colour texture file"}}) {
    try {
      parse_heightfield(entry);
      ADD_FAILURE() << entry << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace heightmarch
