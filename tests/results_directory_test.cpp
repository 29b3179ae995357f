// Results nobody can overwrite or redirect: the atomic writer never follows a link nor clobbers a
// file it did not create; every command that writes checks and locks its --out before any work and
// refuses one that holds another run's results unless --replace; maps sharing a file name keep a
// label each.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "experiment/configuration.hpp"
#include "experiment/suite_plan.hpp"
#include "heightmarch/error.hpp"
#include "io/atomic_file.hpp"
#include "io/images.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

namespace fs = std::filesystem;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// A link planted at the final name is replaced, not written through; the victim keeps its bytes.
TEST(AtomicFile, ReplacesALinkAtTheFinalNameWithoutFollowingIt) {
  const std::string dir = test::temp_dir("atomic-link");
  std::ofstream(dir + "/victim") << "precious";
  for (const std::string name : {"metrics.json", "render.png"}) {
    fs::create_symlink(dir + "/victim", dir + "/" + name);
    if (name == "render.png")
      write_rgb8(dir + "/" + name, 2, 1, {255, 0, 0, 0, 255, 0});
    else
      write_file_atomically(dir + "/" + name, "{}");
    EXPECT_FALSE(fs::is_symlink(dir + "/" + name)) << name;
    EXPECT_EQ(read_text(dir + "/victim"), "precious") << name;
  }
  for (const auto& entry : fs::directory_iterator(dir))  // no temporary left behind
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

// Two writers of one name never share a temporary: each is a new file of its own.
TEST(AtomicFile, TemporariesAreCreatedExclusively) {
  const std::string path = test::temp_dir("atomic-exclusive") + "/out.txt";
  AtomicFile a(path), b(path);
  a.append("first");
  b.append("second");
  a.commit();
  EXPECT_EQ(read_text(path), "first");
  b.commit();
  EXPECT_EQ(read_text(path), "second");
}

// A bad --out is found before any measuring (claims would measure for minutes), and a directory
// holding another run's results, or locked by one, is refused by every command that writes.
TEST(RunDirectory, EveryCommandChecksItsOutBeforeAnyWork) {
  const std::string dir = test::temp_dir("guard");
  std::ofstream(dir + "/a_file") << "";
  fs::create_directories(dir + "/suite_run");
  std::ofstream(dir + "/suite_run/measurements.json") << "{}";
  fs::create_directories(dir + "/trace_run");
  std::ofstream(dir + "/trace_run/metrics.json") << "{}";
  fs::create_directories(dir + "/linked");
  fs::create_symlink(dir + "/victim", dir + "/linked/.lock");
  struct Case {
    std::string out, message;
  };
  const std::vector<Case> cases = {
      {"/dev/null", "/dev/null: is a character device, not a directory"},
      {dir + "/a_file", "a_file: is a regular file, not a directory"},
      {dir + "/a_file/child", "a_file/child: cannot create the directory"},
      {dir + "/suite_run", "suite_run: already holds a run's results (measurements.json)"},
      {dir + "/trace_run", "trace_run: already holds a run's results (metrics.json)"},
      {dir + "/linked", "linked: cannot write into it (its .lock"},
  };
  // Every case with claims (whose default --out is "."), one with each other command: one guard.
  const auto refused = [](const std::string& command, const Case& c) {
    const auto r = test::run_cli(command + " --out " + c.out);
    EXPECT_EQ(r.status, 2) << command << " --out " << c.out << ": " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << command << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << command << ": " << r.output;
  };
  for (const Case& c : cases) refused("claims --quick", c);
  refused("suite --quick --no-glsl", cases[3]);
  refused("trace --size 8x8", cases[2]);
  refused("glsl --size 8x8", cases[4]);
  EXPECT_FALSE(fs::exists(dir + "/victim"));  // the planted .lock was never created through
  // A lock another run holds.
  const int fd = ::open((dir + "/trace_run/.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  const auto locked = test::run_cli("claims --quick --replace --out " + dir + "/trace_run");
  ::close(fd);
  EXPECT_EQ(locked.status, 2) << locked.output;
  EXPECT_NE(locked.output.find("another run is writing into this directory"), std::string::npos)
      << locked.output;
}

// --replace removes the earlier run's files (a link among them goes, its target stays) and writes anew.
TEST(RunDirectory, ReplaceRemovesTheEarlierRunsFiles) {
  const std::string dir = test::temp_dir("replace");
  std::ofstream(dir + "/target") << "kept";
  fs::create_directories(dir + "/out");
  std::ofstream(dir + "/out/measurements.json") << "{}";
  std::ofstream(dir + "/out/report.md") << "old";
  std::ofstream(dir + "/out/notes.txt") << "mine";
  fs::create_symlink(dir + "/target", dir + "/out/render.png");
  const auto r = test::run_cli("trace --res 16 --size 8x8 --repetitions 1 --replace --out " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/out/measurements.json"));
  EXPECT_FALSE(fs::exists(dir + "/out/report.md"));
  EXPECT_FALSE(fs::is_symlink(dir + "/out/render.png"));
  EXPECT_FALSE(fs::exists(dir + "/out/INCOMPLETE"));
  EXPECT_TRUE(fs::exists(dir + "/out/metrics.json"));
  EXPECT_EQ(read_text(dir + "/out/notes.txt"), "mine");
  EXPECT_EQ(read_text(dir + "/target"), "kept");
}

// Maps that share a file name keep a label each (their paths), in the plan, the rows and the
// benchmark names (a slash kept as %2F: names are split at '/').
TEST(RunDirectory, MapsSharingAFileNameKeepALabelEach) {
  const std::string dir = test::temp_dir("labels");
  fs::create_directories(dir + "/a");
  fs::create_directories(dir + "/b");
  for (const char* sub : {"/a/rock.png", "/b/rock.png", "/c.png"})
    write_rgb8(dir + sub, 2, 2, std::vector<std::uint8_t>(12, 9));
  const std::vector<HeightfieldSource> extra = {
      parse_heightfield(dir + "/a/rock.png"), parse_heightfield(dir + "/b/rock.png"),
      parse_heightfield(dir + "/c.png"), parse_heightfield(dir + "/a/rock.png")};
  PlanSettings settings = suite_settings(true, 1);
  settings.heightfields.insert(settings.heightfields.end(), extra.begin(), extra.end());
  give_unique_labels(settings.heightfields);  // as the options' maps get them
  std::vector<std::string> labels;
  for (const HeightfieldSource& h : settings.heightfields) labels.push_back(h.label());
  const std::vector<std::string> expected_tail = {dir + "/a/rock.png", dir + "/b/rock.png", "c.png"};
  ASSERT_GE(labels.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(labels.end() - 3, labels.end()),
            expected_tail);  // the repeated one once
  std::vector<std::string> claim_labels;
  for (const Configuration& c : claims_plan(settings))
    if (std::find(claim_labels.begin(), claim_labels.end(), c.heightfield.label()) == claim_labels.end())
      claim_labels.push_back(c.heightfield.label());
  for (const std::string& label : expected_tail)
    EXPECT_NE(std::find(claim_labels.begin(), claim_labels.end(), label), claim_labels.end()) << label;
  Configuration c = claims_plan(settings).back();
  c.heightfield = settings.heightfields[settings.heightfields.size() - 3];
  std::string escaped;
  for (char ch : dir + "/a/rock.png") escaped += ch == '/' ? std::string("%2F") : std::string(1, ch);
  EXPECT_NE(benchmark_name(c, 2, 2).find("/heightfield:" + escaped + "/"), std::string::npos)
      << benchmark_name(c, 2, 2);
  // A file named like a builtin, given bare, would share its label: one clear line.
  std::vector<HeightfieldSource> clash = {parse_heightfield("builtin:bricks"),
                                          parse_heightfield(dir + "/c.png")};
  clash.back().path = "bricks";
  EXPECT_THROW(give_unique_labels(clash), InputError);
}

}  // namespace
}  // namespace heightmarch
