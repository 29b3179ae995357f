// The CLI end to end: outputs written, and bad input answered with one clear line and a
// non-zero exit, never a crash.
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "test_support.hpp"

namespace heightmarch {
namespace {

namespace fs = std::filesystem;

struct BadInput {
  std::string name;
  std::string arguments;
  std::string message;  // expected in the one-line error
};

std::string write_text(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(Cli, TraceWritesItsFourFiles) {
  const std::string out = test::temp_dir("trace-out");
  const auto r = test::run_cli(
      "trace --heightmap builtin:bricks --res 128 --size 96x64 --technique pom --layers 32 --out " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* file : {"hits.exr", "error.png", "render.png", "metrics.json"})
    EXPECT_GT(fs::file_size(out + "/" + file), 100u) << file;
  std::ifstream json(out + "/metrics.json");
  const std::string text((std::istreambuf_iterator<char>(json)), {});
  for (const char* key : {"\"technique\": \"pom\"", "\"layers\": \"32\"", "\"rays_per_second\"", "\"errors\"",
                          "\"uv_error_p99\"", "\"wrong_surface_rate\"", "\"commit\"", "\"rounds\""})
    EXPECT_NE(text.find(key), std::string::npos) << key;
}

TEST(Cli, RaysFromCsvKeepTheirOrder) {
  const std::string dir = test::temp_dir("rays-csv");
  const std::string csv =
      write_text(dir, "rays.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,0,1\n0.25,0.75,0.6,0,0.8\n0.1,0.2,0,-0.6,0.8\n");
  const auto r =
      test::run_cli("trace --heightmap builtin:flat --res 16 --technique steep --layers 10 --rays " + csv +
                    " --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(dir + "/out/rays.csv");
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_EQ(
      header,
      "tx,ty,vx,vy,vz,u,v,depth,samples,shadow,exact_u,exact_v,exact_depth,uv_error_texels,exact_visibility");
  EXPECT_EQ(first.rfind("0.5,0.5,0,0,1,", 0), 0u) << first;
  EXPECT_EQ(second.rfind("0.25,0.75,0.6", 0), 0u) << second;
}

// rays.csv carries the shadow factor and the exact visibility per ray, so a shadow run can be
// checked ray by ray: on bricks, some rays are lit and some not, and the factor dims some.
TEST(Cli, RaysCsvCarriesTheShadowPerRay) {
  const std::string dir = test::temp_dir("rays-shadow");
  const RayBatch rays = test::random_rays(300, 75.0, 11);
  std::string text = "tx,ty,vx,vy,vz\n";
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (!rays.is_padding(i))
      text += std::to_string(rays.tx[i]) + "," + std::to_string(rays.ty[i]) + "," +
              std::to_string(rays.vx[i]) + "," + std::to_string(rays.vy[i]) + "," +
              std::to_string(rays.vz[i]) + "\n";
  const std::string csv = write_text(dir, "rays.csv", text);
  const auto r = test::run_cli(
      "trace --heightmap builtin:bricks --res 64 --technique shadow --layers 16 --repetitions 1 --rays " +
      csv + " --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(dir + "/out/rays.csv");
  std::string line;
  std::getline(in, line);
  const auto fields = [](const std::string& text) {
    std::vector<std::string> out(1);
    for (char c : text)
      if (c == ',')
        out.emplace_back();
      else
        out.back().push_back(c);
    return out;
  };
  const std::vector<std::string> header = fields(line);
  const auto column = [&](const char* name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t shadow_column = column("shadow"), exact_column = column("exact_visibility");
  ASSERT_LT(exact_column, header.size()) << line;
  std::size_t rows = 0, dimmed = 0, lit = 0, unlit = 0;
  while (std::getline(in, line)) {
    ++rows;
    const std::vector<std::string> row = fields(line);
    ASSERT_EQ(row.size(), header.size()) << line;
    const double shadow = std::stod(row[shadow_column]);
    const std::string& exact = row[exact_column];
    EXPECT_TRUE(shadow >= 0.0 && shadow <= 1.0) << line;
    EXPECT_TRUE(exact == "0" || exact == "1") << line;
    dimmed += shadow < 1.0;
    lit += exact == "1";
    unlit += exact == "0";
  }
  EXPECT_EQ(rows, 300u);
  EXPECT_GT(dimmed, 0u);
  EXPECT_GT(lit, 0u);
  EXPECT_GT(unlit, 0u);
}

// More than a million rays with --out: per-ray files only (an N x 1 PNG is beyond libpng's width).
TEST(Cli, AMillionRaysFromCsv) {
  const std::string dir = test::temp_dir("million");
  const int rays = 1000001;
  {
    std::ofstream csv(dir + "/rays.csv");
    csv << "tx,ty,vx,vy,vz\n";
    for (int i = 0; i < rays; ++i) csv << (i % 1000) / 1000.0 << "," << (i / 1000) / 1000.0 << ",0.6,0,0.8\n";
  }
  const auto r = test::run_cli("trace --res 64 --technique steep --layers 8 --json --repetitions 1 --rays " +
                               dir + "/rays.csv --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output.substr(0, 500);
  EXPECT_NE(r.output.find("\"rays\": 1000001"), std::string::npos) << r.output.substr(0, 500);
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir + "/out"))
    files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{".lock", "metrics.json", "rays.csv"}));
  std::ifstream out(dir + "/out/rays.csv");
  const auto lines = std::count(std::istreambuf_iterator<char>(out), {}, '\n');
  EXPECT_EQ(lines, rays + 1);
}

// --channel picks the depth of a multi-channel image: R = 0, G = 128/255, B = 1 at a straight-down ray.
TEST(Cli, ChannelPicksTheDepth) {
  const std::string dir = test::temp_dir("channel");
  std::vector<std::uint8_t> rgb(16 * 16 * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = 0;
    rgb[i + 1] = 128;
    rgb[i + 2] = 255;
  }
  auto image = OIIO::ImageOutput::create(dir + "/rgb.png");
  ASSERT_TRUE(image && image->open(dir + "/rgb.png", OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(image->write_image(OIIO::TypeDesc::UINT8, rgb.data()) && image->close());
  const std::string rays = write_text(dir, "down.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,0,1\n");
  for (const auto& [channel, depth] : std::vector<std::pair<std::string, std::string>>{
           {"", ",0,"}, {"r", ",0,"}, {"1", ",0.5019608,"}, {"g", ",0.5019608,"}, {"b", ",1,"}}) {
    const std::string out = dir + "/out" + channel;
    const auto r = test::run_cli("trace --json --repetitions 1 --heightmap " + dir + "/rgb.png --rays " +
                                 rays + " --out " + out + (channel.empty() ? "" : " --channel " + channel));
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(out + "/rays.csv");
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_NE(row.find("0.5,0.5,0,0,1,0.5,0.5" + depth), std::string::npos)
        << "--channel " << channel << ": " << row;
  }
}

// A normal map in RGB with the depth in alpha: trace refuses to read its constant red channel as
// the depth, in one line naming the channel that varies; the alpha read as meant (--channel, or
// the entry's own :channel=) and the flat map asked for (--allow-flat) run.
TEST(Cli, TheDepthInAlphaIsNotReadAsAFlatRed) {
  const std::string dir = test::temp_dir("depth-in-alpha");
  std::vector<std::uint8_t> rgba(16 * 16 * 4);
  for (std::size_t i = 0; i < rgba.size(); i += 4) {
    rgba[i] = rgba[i + 1] = 128;
    rgba[i + 2] = 255;
    rgba[i + 3] = std::uint8_t(i / 4 % 16 * 16);
  }
  auto image = OIIO::ImageOutput::create(dir + "/rgba.png");
  OIIO::ImageSpec spec(16, 16, 4, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  ASSERT_TRUE(image && image->open(dir + "/rgba.png", spec));
  ASSERT_TRUE(image->write_image(OIIO::TypeDesc::UINT8, rgba.data()) && image->close());
  const std::string trace = "trace --size 16x16 --repetitions 1 --heightmap " + dir + "/rgba.png";
  auto r = test::run_cli(trace);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(
      r.output.find(
          "rgba.png: channel 0 (R), read as the depth, is constant (0.501961) while channel 3 (A) varies"),
      std::string::npos)
      << r.output;
  for (const std::string& meant : {trace + " --channel a", trace + ":channel=a"}) {
    r = test::run_cli(meant);
    EXPECT_EQ(r.status, 0) << meant << ": " << r.output;
  }
  r = test::run_cli(trace + " --allow-flat");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + dir + "/rgba.png: channel 0 (R), read as the depth, is constant"),
            std::string::npos)
      << r.output;
}

// The suite reads each map as its user means it: --convention, --channel and --wrap for every
// file, and each entry's own options over them, recorded in measurements.json.
TEST(Cli, SuiteReadsEachMapAsMeant) {
  const std::string dir = test::temp_dir("suite-maps");
  std::vector<std::uint8_t> ramp(32 * 32 * 2);
  for (std::size_t i = 0; i < ramp.size(); i += 2) ramp[i] = ramp[i + 1] = std::uint8_t(i / 2 % 32 * 8);
  auto image = OIIO::ImageOutput::create(dir + "/ramp.png");
  ASSERT_TRUE(image && image->open(dir + "/ramp.png", OIIO::ImageSpec(32, 32, 2, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(image->write_image(OIIO::TypeDesc::UINT8, ramp.data()) && image->close());
  const auto r =
      test::run_cli("suite --quick --no-glsl --no-builtins --heightmap " + dir + "/ramp.png," + dir +
                    "/ramp.png:channel=1:wrap=clamp:convention=depth --convention height --parts matrix "
                    "--techniques pom --layers 8 --isas scalar --threads 1 --repetitions 1 --out " +
                    dir + "/run");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto unpacked = test::run_command("gzip -dc " + dir + "/run/measurements.json.gz");
  ASSERT_EQ(unpacked.status, 0) << unpacked.output;
  const std::string& json = unpacked.output;
  const auto field = [&](const std::string& entry,
                         const std::string& name) {  // of the entry's heightfield object
    const std::size_t at = json.find("\"source\": \"" + dir + entry + "\"");
    const std::size_t key = json.find("\"" + name + "\": ", at);
    return at == std::string::npos || key == std::string::npos
               ? "(none)"
               : json.substr(key, json.find_first_of(",\n}", key) - key);
  };
  EXPECT_EQ(field("/ramp.png:convention=height", "convention"), "\"convention\": \"height\"");
  EXPECT_EQ(field("/ramp.png:convention=height", "channel"), "\"channel\": 0");
  EXPECT_EQ(field("/ramp.png:convention=height", "wrap"), "\"wrap\": \"repeat\"");
  EXPECT_EQ(field("/ramp.png:channel=1:wrap=clamp", "convention"), "\"convention\": \"depth\"");
  EXPECT_EQ(field("/ramp.png:channel=1:wrap=clamp", "channel"), "\"channel\": 1");
  EXPECT_EQ(field("/ramp.png:channel=1:wrap=clamp", "wrap"), "\"wrap\": \"clamp\"");
}

// What a ray file may hold: a UTF-8 byte order mark, 1e-50 (0 as a float), V.z = 5e-7 exactly.
TEST(Cli, RaysFileEdgeValuesAreAccepted) {
  const std::string dir = test::temp_dir("edge-rays");
  for (const std::string& text : {std::string("\xEF\xBB\xBFtx,ty,vx,vy,vz\n0.5,0.5,0,0,1\n"),
                                  std::string("tx,ty,vx,vy,vz\n0.5,0.5,1e-50,0,1\n"),
                                  std::string("tx,ty,vx,vy,vz\n0.5,0.5,0,1,5e-7\n")}) {
    // A small scale keeps the V.z = 5e-7 path within the exact reference's 2^20 cells.
    const auto r = test::run_cli("trace --res 16 --scale 0.001 --repetitions 1 --json --rays " +
                                 write_text(dir, "rays.csv", text));
    EXPECT_EQ(r.status, 0) << text << ": " << r.output.substr(0, 300);
  }
}

// At the default scale that ray crosses more cells than the exact reference walks: one line.
TEST(Cli, GrazingRayBeyondTheExactLimitIsRefused) {
  const std::string dir = test::temp_dir("grazing-rays");
  const auto r = test::run_cli("trace --scale 1 --repetitions 1 --rays " +
                               write_text(dir, "rays.csv", "tx,ty,vx,vy,vz\n0.5,0.5,1,0,6e-7\n"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("ray 1 grazes the surface"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("it needs V.z >="), std::string::npos) << r.output;
}

// HEIGHTMARCH_MEMORY_LIMIT: bytes with K, M, G, T suffixes; anything else is one line, exit 2.
TEST(Cli, MemoryLimitIsParsedStrictly) {
  const std::string trace =
      std::string(HEIGHTMARCH_CLI) + " trace --res 16 --size 8x8 --repetitions 1 --json";
  for (const char* bad : {"1e30", "inf", "2e19", "10X", "abc", "-1", "0", "nan", "99999999999999999999"}) {
    const auto r = test::run_command("HEIGHTMARCH_MEMORY_LIMIT='" + std::string(bad) + "' " + trace);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.output;
    EXPECT_EQ(r.output.rfind("heightmarch: HEIGHTMARCH_MEMORY_LIMIT='" + std::string(bad) + "': ", 0), 0u)
        << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
  for (const char* good : {"1T", "512M", "1.5GiB", "1073741824"}) {
    const auto r = test::run_command("HEIGHTMARCH_MEMORY_LIMIT=" + std::string(good) + " " + trace);
    EXPECT_EQ(r.status, 0) << good << ": " << r.output.substr(0, 300);
  }
}

// The budget counts what a run holds: --tile 1 pads every tile of one ray to 32.
TEST(Cli, MemoryBudgetCountsTilePadding) {
  const auto r = test::run_command("HEIGHTMARCH_MEMORY_LIMIT=200M " + std::string(HEIGHTMARCH_CLI) +
                                   " trace --tile 1 --json");
  EXPECT_EQ(r.status, 2) << r.output.substr(0, 300);
  EXPECT_NE(r.output.find("a 1024x1024 view needs 5.5 GiB, more than the "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" left of the 200.0 MiB budget"), std::string::npos) << r.output;
}

TEST(Cli, JsonHasTheSpecKeys) {
  const auto r = test::run_cli(
      "trace --res 64 --size 32x32 --technique relief --layers 8-32 --json --threads 1 --filter trilinear");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"filter\": \"trilinear\""), std::string::npos) << r.output;
  for (const char* key : {"technique",
                          "layers",
                          "backend",
                          "threads",
                          "width",
                          "height",
                          "rays",
                          "rays_per_second",
                          "samples_per_second",
                          "samples_per_ray",
                          "errors",
                          "uv_error_mean",
                          "uv_error_rms",
                          "uv_error_p50",
                          "uv_error_p95",
                          "uv_error_p99",
                          "uv_error_max",
                          "wrong_surface_rate",
                          "depth_error_mean",
                          "discarded",
                          "median",
                          "min",
                          "max",
                          "rounds",
                          "repetitions"})
    EXPECT_NE(r.output.find("\"" + std::string(key) + "\""), std::string::npos) << key;
}

TEST(Cli, HelpAndVersion) {
  for (const char* args : {"-h", "--help"}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.status, 0) << r.output;
    for (const char* command : {"trace", "glsl", "suite", "claims", "recommend"})
      EXPECT_NE(r.output.find(command), std::string::npos);
  }
  const auto version = test::run_cli("--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.output.rfind("heightmarch ", 0), 0u) << version.output;
  EXPECT_NE(version.output.find("\nISAs this CPU runs: " + runnable_isa_names() + "\n"), std::string::npos)
      << version.output;
  // The help lists every technique of the registry.
  const auto trace_help = test::run_cli("trace --help");
  for (const TechniqueInfo& t : techniques())
    EXPECT_NE(trace_help.output.find(std::string(t.name)), std::string::npos) << t.name;
}

// An ISA the CPU does not run (simulated with the cap, which hides sse4.2 from any x86-64 CPU's
// list): the refusal names the variable or option and the ISAs this CPU runs.
TEST(Cli, AnIsaTheCpuLacksIsNamedWithTheIsasItRuns) {
  if (all_isas().size() < 2) GTEST_SKIP() << "this architecture's list holds the scalar reference alone";
  const std::string capped = "HEIGHTMARCH_MAX_ISA=scalar ";
  const std::string runs = "; it runs scalar (capped by HEIGHTMARCH_MAX_ISA=scalar)\n";
  auto r = test::run_command(capped + "HEIGHTMARCH_ISA=sse4.2 " HEIGHTMARCH_CLI " trace --size 8x8");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.output, "heightmarch: HEIGHTMARCH_ISA=sse4.2: this CPU does not run sse4.2" + runs);
  r = test::run_command(capped + HEIGHTMARCH_CLI " trace --size 8x8 --isa sse4.2");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.output, "heightmarch: --isa sse4.2: this CPU does not run sse4.2" + runs);
  r = test::run_command(capped + HEIGHTMARCH_CLI " suite --quick --isas scalar,sse4.2 --dry-run");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.output, "heightmarch: --isas sse4.2: this CPU does not run sse4.2" + runs);
  r = test::run_command("HEIGHTMARCH_MAX_ISA=avx3 " HEIGHTMARCH_CLI " --version");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.output.rfind("heightmarch: HEIGHTMARCH_MAX_ISA=avx3: not an ISA (scalar", 0), 0u) << r.output;
}

// claims without --out writes a fresh directory under results/, as the suite does, never into the
// current directory.
TEST(Cli, ClaimsWriteAFreshRunDirectoryByDefault) {
  const std::string dir = test::temp_dir("claims-default");
  const auto r = test::run_command("cd " + dir +
                                   " && " HEIGHTMARCH_CLI
                                   " claims --quick --no-builtins --heightmap builtin:waves --repetitions 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/claims.md"));
  std::vector<fs::path> runs;
  for (const auto& entry : fs::directory_iterator(dir + "/results")) runs.push_back(entry.path());
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_NE(runs[0].filename().string().find("-claims-quick"), std::string::npos) << runs[0];
  for (const char* file : {"claims.md", "claims.json", "measurements.json", "recommendation.json"})
    EXPECT_TRUE(fs::exists(runs[0] / file)) << file;
  EXPECT_NE(r.output.find("claims: done in "), std::string::npos) << r.output;
}

// A suite never writes into a directory that holds a run, nor into one another run holds.
TEST(Cli, SuiteRefusesAnOccupiedRunDirectory) {
  const std::string dir = test::temp_dir("occupied");
  write_text(dir, "measurements.json", "{}");
  auto r = test::run_cli("suite --quick --no-glsl --out " + dir);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("already holds a run"), std::string::npos) << r.output;
  const std::string locked = test::temp_dir("locked");
  const int fd = ::open((locked + "/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  r = test::run_cli("suite --quick --no-glsl --out " + locked);
  ::close(fd);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("another run is writing into this directory"), std::string::npos) << r.output;
}

// A gallery/ planted as a link in --out would take the gallery's images wherever it points:
// refused before any work, and the directory is not marked as a run.
TEST(Cli, SuiteRefusesAGalleryThatIsALink) {
  const std::string dir = test::temp_dir("gallery-link");
  fs::create_directories(dir + "/elsewhere");
  fs::create_directories(dir + "/out");
  fs::create_directory_symlink(dir + "/elsewhere", dir + "/out/gallery");
  const auto r =
      test::run_cli("suite --quick --no-glsl --techniques pom --parts gallery --out " + dir + "/out");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "heightmarch: " + dir +
                          "/out/gallery: is a link, not a directory of the run's own to write into\n");
  EXPECT_TRUE(fs::is_empty(dir + "/elsewhere"));
  EXPECT_FALSE(fs::exists(dir + "/out/INCOMPLETE"));
}

// The report (Python) says why it refuses a run in its one line; the tool adds none of its own.
TEST(Cli, ReportRefusalIsOneLine) {
  const std::string dir = test::temp_dir("report-refused");
  write_text(dir, "measurements.json", "{\"format\": \"heightmarch-measurements\", \"format_version\": 2}");
  const auto r = test::run_cli("report " + dir);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

// heightmarch-bench times the suite's plan: for the same filters, window (the suite's, around) and
// filter of the depth map, it lists the suite's timed configurations (both print plan_line();
// compared without the purposes, which a configuration the bench also times for another part
// joins); beside them only the Highway forms (the port, POM's structure) and the technique x
// layers matrix at the ISAs other than the widest asked for.
TEST(Cli, BenchTimesTheSuitesPlan) {
  const std::string bench =
      std::filesystem::path(HEIGHTMARCH_CLI).parent_path().string() + "/heightmarch-bench";
  if (!std::filesystem::exists(bench))
    GTEST_SKIP() << "heightmarch-bench is not built here (HEIGHTMARCH_BUILD_BENCHMARKS=OFF)";
  const auto lines = [](const std::string& output, bool timed_only) {
    std::set<std::string> out;
    std::istringstream in(output);
    for (std::string line; std::getline(in, line);)
      if (line.find('\t') != std::string::npos &&
          (!timed_only || line.find("\ttimed\t") != std::string::npos))
        out.insert(line.substr(0, line.rfind('\t')));
    return out;
  };
  const std::string widest = to_string(best_isa());
  for (const auto& [parts, filter] :
       {std::pair<std::string, std::string>{"matrix,isa,glsl,roofline,exact", "bilinear"},
        {"matrix,isa,naive", "trilinear"}}) {
    for (const std::string& isas : {widest, "scalar," + widest}) {
      SCOPED_TRACE(parts + " at " + isas + ", " + filter);
      const auto suite = test::run_cli(
          "suite --dry-run --no-builtins --heightmap builtin:bricks --techniques pom,maxmip "
          "--layers 8,8-32 --threads 1 --isas " +
          isas + " --parts " + parts + " --filter " + filter);
      const auto benched =
          test::run_command(bench +
                            " --hm_dry_run --hm_views=around --hm_heightfields=builtin:bricks "
                            "--hm_techniques=pom,maxmip --hm_layers=8,8-32 --hm_threads=1 --hm_isas=" +
                            isas + " --hm_parts=" + parts + " --hm_filters=" + filter);
      ASSERT_EQ(suite.status, 0) << suite.output;
      ASSERT_EQ(benched.status, 0) << benched.output;
      const std::set<std::string> in_suite = lines(suite.output, true),
                                  in_bench = lines(benched.output, false);
      ASSERT_FALSE(in_suite.empty());
      for (const std::string& line : in_suite)
        EXPECT_EQ(in_bench.count(line), 1u) << "not in the bench: " << line;
      for (const std::string& line : in_bench) {
        if (in_suite.count(line)) continue;
        const bool highway = line.find("\thighway") != std::string::npos;  // the port, and the structured POM
        const bool matrix_elsewhere = line.find("\ttrace\t") != std::string::npos &&
                                      line.find("\t" + widest + "\t") == std::string::npos;
        EXPECT_TRUE(highway || matrix_elsewhere) << "only in the bench: " << line;
      }
    }
  }
}

// heightmarch-bench's own flags are checked like the CLI's, and every Google Benchmark flag before
// Google Benchmark sees it (a negative repetition count aborted in vector::reserve, a NaN minimum
// time hung, an unknown format or a broken filter exited 0): one line, exit 2.
TEST(Cli, BenchFlagsAreChecked) {
  const std::string bench =
      std::filesystem::path(HEIGHTMARCH_CLI).parent_path().string() + "/heightmarch-bench";
  if (!std::filesystem::exists(bench))
    GTEST_SKIP() << "heightmarch-bench is not built here (HEIGHTMARCH_BUILD_BENCHMARKS=OFF)";
  auto run = [&](const std::string& args) { return test::run_command(bench + " " + args); };
  for (const char* args : {"--hm_size=12x",
                           "--hm_size=abc",
                           "--hm_heightfields=nope",
                           "--hm_min_time=nan",
                           "--hm_layers=0",
                           "--hm_isas=neon",
                           "--frobnicate",
                           "--benchmark_repetitions=-1",
                           "--benchmark_repetitions=0",
                           "--benchmark_repetitions=99999999999",
                           "--benchmark_repetitions=abc",
                           "--benchmark_min_time=nan",
                           "--benchmark_min_time=-1",
                           "--benchmark_min_warmup_time=inf",
                           "--benchmark_format=xml",
                           "--benchmark_out_format=csv",
                           "--benchmark_filter=[",
                           "--benchmark_color=maybe",
                           "--benchmark_list_tests=maybe",
                           "--benchmark_out=",
                           "--benchmark_context=x",
                           "--benchmark_time_unit=ps",
                           "--benchmark_frobnicate=1",
                           "--benchmark_repetitions",
                           "--benchmark_repetitions=3 --benchmark_repetitions=4",
                           "--hm_threads=1,1",
                           "--hm_layers=8,8",
                           "--hm_filters=bilinear,bilinear",
                           "--hm_heightfields=bricks,builtin:bricks"}) {
    const auto r = run(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("heightmarch-bench: ", 0), 0u) << args << ": " << r.output;
  }
  const auto help = run("--help");
  EXPECT_EQ(help.status, 0) << help.output;
  for (const char* flag : {"--hm_size", "--hm_res", "--hm_heightfields", "--hm_layers", "--hm_threads",
                           "--hm_isas", "--hm_min_time", "--benchmark_filter"})
    EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
  // Names carry the view and depth-map sizes, never min_time.
  const auto list =
      run("--hm_size=64 --hm_res=32 --hm_heightfields=bricks --hm_layers=8 --benchmark_list_tests=true");
  EXPECT_EQ(list.status, 0) << list.output;
  EXPECT_NE(list.output.find("BM_Trace/heightfield:bricks/technique:pom/layers:8/isa:scalar/threads:1/"
                             "view:64x64/depth_map:32x32"),
            std::string::npos)
      << list.output;
  EXPECT_EQ(list.output.find("min_time"), std::string::npos);
}

class CliBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliBadInput, OneClearLineAndNonZeroExit) {
  const BadInput& c = GetParam();
  const auto r = test::run_cli(c.arguments);
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_LT(r.status, 128) << "crashed: " << r.output;
  EXPECT_NE(r.output.find(c.message), std::string::npos) << "output was: " << r.output;
  EXPECT_EQ(r.output.rfind("heightmarch: ", 0), 0u) << r.output;
  EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

// truncated.jpg: a JPEG cut in its scan data; huge.jpg: 400 bytes whose header declares 16000 x 16000.
void write_jpegs(const std::string& d) {
  const int side = 256;
  std::vector<std::uint8_t> grey(side * side);
  for (int i = 0; i < side * side; ++i) grey[i] = std::uint8_t((i * 7 + i / side * 13) % 251);
  auto out = OIIO::ImageOutput::create(d + "/whole.jpg");
  ASSERT_TRUE(out && out->open(d + "/whole.jpg", OIIO::ImageSpec(side, side, 1, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, grey.data()) && out->close());
  std::ifstream in(d + "/whole.jpg", std::ios::binary);
  std::string jpeg((std::istreambuf_iterator<char>(in)), {});
  write_text(d, "truncated.jpg", jpeg.substr(0, jpeg.size() / 2));
  const std::size_t sof = jpeg.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  for (std::size_t at : {sof + 5, sof + 7}) {  // height, width: 16000 = 0x3e80
    jpeg[at] = char(0x3e);
    jpeg[at + 1] = char(0x80);
  }
  write_text(d, "huge.jpg", jpeg.substr(0, 400));
}

std::string fixture_dir() {
  static const std::string dir = [] {
    const std::string d = test::temp_dir("bad-input");
    write_text(d, "empty.png", "");
    write_text(d, "notanimage.png", "this is not a png at all, just text\n");
    // A PNG signature and a truncated IHDR.
    write_text(d, "truncated.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0", 18));
    write_text(d, "empty.csv", "");
    write_text(d, "header_only.csv", "tx,ty,vx,vy,vz\n");
    write_text(d, "missing_column.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,1\n");
    write_text(d, "text.csv", "tx,ty,vx,vy,vz\n0.5,abc,0,0,1\n");
    write_text(d, "below.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,0.6,-0.8\n");
    write_text(d, "nan.csv", "tx,ty,vx,vy,vz\n0.5,nan,0,0,1\n");
    write_text(d, "bad_header.csv", "x,y,z\n1,2,3\n");
    write_text(d, "zero.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,0,0\n");
    write_text(d, "huge_value.csv", "tx,ty,vx,vy,vz\n0.5,0.5,1e50,0,1\n");
    // LearnOpenGL's parallax_mapping.fs, whole, as a user might pass it
    write_text(d, "whole.fs",
               "#version 330 core\nout vec4 FragColor;\nuniform sampler2D depthMap;\n"
               "uniform float heightScale;\n// void main() is below\n"
               "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {\n  return texCoords;\n}\n\n"
               "void main()\n{\n  FragColor = vec4(1.0);\n}\n");
    write_text(d, "typo.glsl",
               "// mine\n\nvec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {\n  return texCoordz;\n}\n");
    write_text(d, "nofunction.glsl", "float depthAt(vec2 uv) { return 0.5; }\n");
    write_text(d, "rgb.csv", "tx,ty,vx,vy,vz\n0.5,0.5,0,0,1\n");
    write_text(d, "a_file", "");
    ::mkfifo((d + "/fifo.png").c_str(), 0644);
    write_jpegs(d);
    std::vector<std::uint8_t> rgba(8 * 8 * 4, 128);
    for (std::size_t i = 3; i < rgba.size(); i += 4) rgba[i] = std::uint8_t(i);
    auto alpha = OIIO::ImageOutput::create(d + "/rgba_alpha.png");
    OIIO::ImageSpec spec(8, 8, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (alpha && alpha->open(d + "/rgba_alpha.png", spec)) {
      alpha->write_image(OIIO::TypeDesc::UINT8, rgba.data());
      alpha->close();
    }
    write_text(d, "discard.glsl",
               "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {\n  if (texCoords.x > 0.5) discard;\n  "
               "return texCoords;\n}\n");
    return d;
  }();
  return dir;
}

std::vector<BadInput> bad_inputs() {
  const std::string d = fixture_dir();
  return {
      {"MissingFile", "trace --heightmap /nonexistent/depth.png", "/nonexistent/depth.png"},
      {"EmptyImage", "trace --heightmap " + d + "/empty.png", "empty.png"},
      {"NotAnImage", "trace --heightmap " + d + "/notanimage.png", "notanimage.png"},
      {"TruncatedImage", "trace --heightmap " + d + "/truncated.png", "truncated.png"},
      {"UnknownBuiltin", "trace --heightmap builtin:nope", "nope"},
      {"UnknownTechnique", "trace --technique nope", "unknown technique 'nope'"},
      {"UnknownFilter", "trace --filter nearest", "--filter: nearest not in"},
      {"ZeroLayers", "trace --layers 0", "layer spec '0'"},
      {"ConeZeroLayers", "trace --technique cone --layers 0", "layer spec '0'"},
      {"ConeNegativeRefine", "trace --technique cone --refine -1", "--refine"},
      {"NegativeLayers", "trace --layers -3", "layer spec '-3'"},
      {"ReversedRange", "trace --layers 32-8", "exceeds maximum"},
      {"OpenRange", "trace --layers 8-", "layer spec '8-'"},
      {"HugeLayers", "trace --layers 100000000", "layer spec '100000000'"},
      {"TextLayers", "trace --layers many", "layer spec 'many'"},
      {"NegativeScale", "trace --scale -1", "scale"},
      {"NanScale", "trace --scale nan", "--scale"},
      {"BadSize", "trace --size 0x10", "--size"},
      {"HugeSize", "trace --size 100000x100000", "--size"},
      {"BadRes", "trace --res 0", "--res"},
      {"UnknownOption", "trace --frobnicate", "not expected: --frobnicate"},
      {"MissingValue", "trace --layers", "--layers: 1 required"},
      {"BadWrap", "trace --wrap mirror", "--wrap"},
      {"BadView", "trace --view sweep:95", "THETA"},
      {"BadLight", "trace --technique shadow --light 1,1,-1", "light"},
      {"BadIsa", "trace --isa neon", "--isa neon: unknown ISA (scalar"},
      // Every numeric option's range in one form, never DBL_MAX's 309 digits.
      {"NegativeMaxError", "recommend /nonexistent --max-error -1", "--max-error: must be >= 0, not -1"},
      {"NanMaxWrongSurface", "recommend /nonexistent --max-wrong-surface nan",
       "--max-wrong: must be in [0, 100], not nan"},
      {"ZeroFrames", "recommend /nonexistent --frames 0", "--frames: must be in [1, 1073741824], not 0"},
      {"SuiteZeroScale", "suite --quick --scale 0", "--scale: must be in (0, 1], not 0"},
      {"SuiteZeroRepetitions", "suite --quick --repetitions 0", "--repetitions: must be in [1, 1000], not 0"},
      {"ClaimsNegativeThreads", "claims --quick --threads 2,-1", "--threads: must be in [0, 1024], not -1"},
      {"TraceTextTile", "trace --tile big", "--tile: 'big' is not a number"},
      {"UnknownCommand", "frobnicate", "unknown command"},
      {"EmptyCsv", "trace --rays " + d + "/empty.csv", "empty rays file"},
      {"HeaderOnlyCsv", "trace --rays " + d + "/header_only.csv", "no rays"},
      {"MissingColumnCsv", "trace --rays " + d + "/missing_column.csv", "expected 5 columns"},
      {"TextInCsv", "trace --rays " + d + "/text.csv", "'abc' is not a number"},
      {"RayFromBelowCsv", "trace --rays " + d + "/below.csv", "V.z"},
      {"NanInCsv", "trace --rays " + d + "/nan.csv", "not finite"},
      {"BadHeaderCsv", "trace --rays " + d + "/bad_header.csv", "header must be tx,ty,vx,vy,vz"},
      {"MissingCsv", "trace --rays /nonexistent/rays.csv", "cannot open"},
      {"ZeroVectorCsv", "trace --rays " + d + "/zero.csv", "V is the zero vector"},
      {"HugeValueCsv", "trace --rays " + d + "/huge_value.csv", "vx '1e50' is beyond a float's range"},
      {"NanPhi", "trace --view sweep:30,nan", "PHI must be a finite number"},
      {"GrazingLight", "trace --technique shadow --light 1,0,0.0001", "light direction grazes the plane"},
      {"OutUnderAFile", "trace --size 8x8 --out " + d + "/a_file/out",
       d + "/a_file/out: cannot create the directory"},
      {"DevZeroHeightmap", "trace --heightmap /dev/zero",
       "/dev/zero: is a character device, not a regular file"},
      {"DevZeroRays", "trace --rays /dev/zero", "/dev/zero: is a character device, not a regular file"},
      {"DevZeroShader", "glsl --shader /dev/zero", "/dev/zero: is a character device, not a regular file"},
      {"FifoHeightmap", "trace --heightmap " + d + "/fifo.png", "fifo.png: is a FIFO, not a regular file"},
      {"TruncatedJpeg", "trace --size 8x8 --heightmap " + d + "/truncated.jpg",
       "truncated.jpg: cannot read pixels"},
      {"HugeJpeg", "trace --size 8x8 --heightmap " + d + "/huge.jpg",
       "declares 16000x16000 pixels in only 400 bytes"},
      {"MissingChannel", "trace --size 8x8 --heightmap " + d + "/whole.jpg --channel g", "has no channel 1"},
      {"BadChannel", "trace --size 8x8 --heightmap " + d + "/whole.jpg --channel x", "--channel 'x'"},
      {"ChannelOfBuiltin", "trace --size 8x8 --channel 1",
       "a channel (--channel, :channel=) applies to a depth map file"},
      {"HeightOfBuiltin", "trace --size 8x8 --convention height",
       "applies to a depth map file, not builtin:bricks"},
      {"UnknownEntryOption", "suite --quick --heightmap " + d + "/whole.jpg:chanel=g --dry-run",
       "unknown option 'chanel' (convention, channel, wrap, albedo)"},
      {"SuiteConventionWithoutMaps", "suite --quick --convention height --dry-run",
       "--convention requires --heightmap"},
      {"SuiteDepthInAlpha",
       "suite --quick --no-glsl --heightmap " + d + "/rgba_alpha.png --out " + d + "/suite-alpha",
       "rgba_alpha.png: channel 0 (R), read as the depth, is constant"},
      {"ClaimsDepthInAlpha",
       "claims --quick --heightmap " + d + "/rgba_alpha.png --out " + d + "/claims-alpha",
       "rgba_alpha.png: channel 0 (R), read as the depth, is constant"},
      {"WholeShader", "glsl --size 8x8 --shader " + d + "/whole.fs",
       "whole.fs:10: defines main(): a function vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) is "
       "expected, not a "
       "whole shader"},
      {"ShaderTypo", "glsl --size 8x8 --shader " + d + "/typo.glsl",
       "typo.glsl:4:9: error: `texCoordz' undeclared"},
      {"ShaderWithoutFunction", "glsl --size 8x8 --shader " + d + "/nofunction.glsl",
       "does not define vec2 ParallaxMapping"},
      {"BadExtraHeightmapInSuite",
       "suite --quick --no-glsl --heightmap " + d + "/truncated.jpg --out " + d + "/suite",
       "truncated.jpg: cannot read pixels"},
      {"DiscardingShader", "glsl --size 16x16 --views single --repetitions 1 --shader " + d + "/discard.glsl",
       "discard.glsl: left 128 of 256 rays without a hit (does it call discard?)"},
      {"NoSuchGlPath", "glsl --size 8x8 --gl vulkan", "--gl vulkan: not a GL path (osmesa|egl)"},
      {"DeviceWithOsmesa", "glsl --size 8x8 --gl osmesa --gl-device software", "OSMesa has no devices"},
      {"DeviceThatIsAPath", "glsl --size 8x8 --gl-device ../dri/card0",
       "--gl-device ../dri/card0: not a device"},
      {"NoSuchDevice", "glsl --size 8x8 --gl-device 63",
       "--gl-device 63: EGL lists no such device; it lists 0 "},
      {"SuiteNoSuchGlPath", "suite --quick --gl vulkan --out " + d + "/gl-suite",
       "--gl vulkan: not a GL path"},
  };
}

INSTANTIATE_TEST_SUITE_P(Trace, CliBadInput, ::testing::ValuesIn(bad_inputs()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace heightmarch
