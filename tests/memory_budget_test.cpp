// One memory budget, asked before every allocation that scales with the input, holds at the peak:
// a budget below the program's own footprint is refused at start-up; an image is refused from its
// header (its decoder's buffers counted, a PNM file's whole-file read before it is opened); a rays
// file from its size and first lines, however large; and a run that passes stays within it.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <vector>

#include "test_support.hpp"
#include "util/sanitizers.hpp"

namespace heightmarch {
namespace {

// What the tool holds before any input, in MiB, as it says when refusing a budget of 1 byte.
double footprint_mib() {
  static const double mib = [] {
    const auto r = test::run_cli("trace --memory-limit 1");
    std::smatch m;
    return std::regex_search(r.output, m, std::regex("own footprint of ([0-9.]+) MiB")) ? std::stod(m[1])
                                                                                        : 0.0;
  }();
  return mib;
}

std::string limit_above_footprint(double mib) { return std::to_string(int(footprint_mib() + mib)) + "M"; }

void write_image(const std::string& path, int side, int channels, OIIO::TypeDesc type) {
  std::vector<float> pixels(std::size_t(side) * side * channels, 0.5f);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, OIIO::ImageSpec(side, side, channels, type)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
}

TEST(MemoryBudget, BelowTheFootprintIsRefusedAtStartUp) {
  ASSERT_GT(footprint_mib(), 1.0);
  const std::string trace = std::string(HEIGHTMARCH_CLI) + " trace --res 16 --size 8x8 --repetitions 1";
  for (const std::string& how : {"HEIGHTMARCH_MEMORY_LIMIT=20M " + trace, trace + " --memory-limit 20M",
                                 "HEIGHTMARCH_MEMORY_LIMIT=1T " + trace + " --memory-limit 20M"}) {
    const auto r = test::run_command(how);
    EXPECT_EQ(r.status, 2) << how << ": " << r.output;
    EXPECT_NE(r.output.find("a memory budget of 20.0 MiB"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("is below heightmarch's own footprint of"), std::string::npos) << r.output;
  }
  // The option comes before the environment; a malformed one is one line.
  EXPECT_EQ(test::run_command("HEIGHTMARCH_MEMORY_LIMIT=20M " + trace + " --memory-limit 1T").status, 0);
  const auto bad = test::run_command(trace + " --memory-limit 10X");
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.output.rfind("heightmarch: --memory-limit='10X': unknown suffix", 0), 0u) << bad.output;
  for (const char* command : {"trace", "claims"})  // one declaration serves every command
    EXPECT_NE(test::run_cli(std::string(command) + " --help").output.find("--memory-limit"),
              std::string::npos)
        << command;
}

// From the header, before a pixel is read: the depth map and what derives from it (14 bytes a
// texel) and, for a PNG (decoded whole when interlaced), its image in its own type.
// Runs trace over `image` at `over_footprint_mib` above the footprint: refused in one line holding
// `message`, at a peak of no more than the footprint and a little (peaks are not checked in an
// AddressSanitizer build, whose own memory swamps them: util/sanitizers.hpp).
void expect_refused_from_header(const std::string& image, double over_footprint_mib,
                                const std::string& message) {
  const auto r = test::run_with_peak(std::string(HEIGHTMARCH_CLI) + " trace --size 8x8 --heightmap " + image +
                                     " --memory-limit " + limit_above_footprint(over_footprint_mib));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  if (!kAddressSanitizer) {
    EXPECT_LT(r.peak_mib, footprint_mib() + 16) << r.output;
  }
}

TEST(MemoryBudget, ImagesAreRefusedFromTheirHeader) {
  const std::string dir = test::temp_dir("budget-images");
  write_image(dir + "/rgba16.png", 2048, 4, OIIO::TypeDesc::UINT16);
  expect_refused_from_header(dir + "/rgba16.png", 60,
                             "rgba16.png (2048x2048, 4 channels of uint16) needs 88.0 MiB");
  // A PNM file is read whole, twice, when its reader opens it: asked before.
  {
    std::ofstream pfm(dir + "/big.pfm", std::ios::binary);
    pfm << "Pf\n2048 2048\n-1.0\n";
    const std::vector<float> row(2048, 0.5f);
    for (int y = 0; y < 2048; ++y)
      pfm.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * 4));
  }
  expect_refused_from_header(dir + "/big.pfm", 24,
                             "big.pfm (its reader holds the whole file) needs 32.0 MiB");
}

// The budget holds at the peak whatever the run: refused where an allocation would pass it (each
// asks: the load from the header, then the sampler's copy, each pyramid, the rays), or run within it.
TEST(MemoryBudget, HoldsAtThePeak) {
  const std::string dir = test::temp_dir("budget-peak");
  write_image(dir + "/grey.png", 2048, 1, OIIO::TypeDesc::UINT8);
  bool passed = false;
  // An AddressSanitizer build's quarantine keeps freed memory in use: there a run needs more.
  std::vector<double> budgets_above_footprint = {60.0, 100.0, 140.0};
  if (kAddressSanitizer) budgets_above_footprint.push_back(1024.0);
  for (const double above : budgets_above_footprint) {
    const std::string limit = limit_above_footprint(above);
    const auto r = test::run_with_peak(std::string(HEIGHTMARCH_CLI) +
                                       " trace --size 128x128 --repetitions 1 --heightmap " + dir +
                                       "/grey.png --technique maxmip --memory-limit " + limit);
    EXPECT_TRUE(r.status == 0 ||
                (r.status == 2 && r.output.find(" budget (--memory-limit; ") != std::string::npos))
        << limit << ": " << r.output;
    if (!kAddressSanitizer) {
      EXPECT_LE(r.peak_mib, std::stod(limit)) << limit << ": " << r.output;
    }
    passed = passed || r.status == 0;
  }
  EXPECT_TRUE(passed);
}

// A rays file is streamed: its rays estimated from its size and first lines and asked of the
// budget before the rest is read; 3 GB (sparse here) are one line at once, not a minute of reading.
TEST(MemoryBudget, RaysFilesAreBoundedFromTheirSize) {
  const std::string dir = test::temp_dir("budget-rays");
  {
    std::ofstream csv(dir + "/rays.csv");
    csv << "tx,ty,vx,vy,vz\n";
    for (int i = 0; i < 300000; ++i) csv << (i % 1000) / 1000.0 << ",0.5,0.6,0,0.8\n";
  }
  const auto r = test::run_with_peak(std::string(HEIGHTMARCH_CLI) + " trace --res 16 --rays " + dir +
                                     "/rays.csv --memory-limit " + limit_above_footprint(24));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("rays.csv (about "), std::string::npos) << r.output;
  if (!kAddressSanitizer) {
    EXPECT_LT(r.peak_mib, footprint_mib() + 16) << r.output;
  }
  {
    std::ofstream csv(dir + "/huge.csv");
    csv << "tx,ty,vx,vy,vz\n";
    for (int i = 0; i < 2000; ++i) csv << "0.5,0.5,0.6,0,0.8\n";
  }
  std::filesystem::resize_file(dir + "/huge.csv", 3'000'000'000);
  const auto huge = test::run_cli("trace --res 16 --memory-limit 8G --rays " + dir + "/huge.csv");
  EXPECT_EQ(huge.status, 2) << huge.output;
  EXPECT_NE(huge.output.find("huge.csv: about "), std::string::npos) << huge.output;
  EXPECT_NE(huge.output.find("more than the 67108864 a rays file may have"), std::string::npos)
      << huge.output;
  std::filesystem::remove(dir + "/huge.csv");
}

// Every allocation sized by the user's input asks the budget before it is made: an outside
// check's fresh rays (the columns they are drawn into came first: 1.4 GiB taken under a 1 GiB
// budget before it said no), a set of camera poses, a view set, a mip chain. Each runs under a
// small budget and is refused in one line at a peak of the footprint and a little.
TEST(MemoryBudget, UserSizedAllocationsAskFirst) {
  const std::string dir = test::temp_dir("budget-user-sized");
  const auto run = test::run_cli(
      "suite --quick --no-builtins --heightmap builtin:waves --techniques pom --layers 8 --isas scalar "
      "--threads 1 --parts matrix --repetitions 1 --no-glsl --out " +
      dir + "/run");
  ASSERT_EQ(run.status, 0) << run.output;
  {
    std::ofstream poses(dir + "/poses.csv");
    poses << "eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,fov,width,height\n";
    for (int i = 0; i < 64; ++i) poses << "0.5,-1,1,0.5,0.5,0,0,0,1,45,4096,4096\n";
  }
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"recommend " + dir + "/run --max-error 1000 --max-wrong-surface 100 --outside-check 67108864",
            "67108864 fresh rays needs"},
           {"trace --res 16 --views " + dir + "/poses.csv", "64 views of 4096x4096 needs"},
           {"trace --res 16 --views tutorial:4096 --size 1024x768", "4096 views of 1024x768 needs"},
           {"trace --size 8x8 --res 2048 --heightmap builtin:waves --filter trilinear --technique pom",
            " needs "}}) {
    const std::string limit = limit_above_footprint(64);
    const auto r =
        test::run_with_peak(std::string(HEIGHTMARCH_CLI) + " " + args + " --memory-limit " + limit);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find(" budget (--memory-limit; "), std::string::npos) << args << ": " << r.output;
    if (!kAddressSanitizer) {
      EXPECT_LE(r.peak_mib, std::stod(limit)) << args << ": " << r.output;
    }
  }
}

}  // namespace
}  // namespace heightmarch
