// Error lines quote untrusted text escaped: printable() on its own, and the CLI's error lines for a
// file name, an option's value and a field of a rays file that carry terminal escapes and raw bytes;
// the JSON writer's strings, and the summaries that name the user's files, by the same rule.
#include <gtest/gtest.h>

#include <fstream>

#include "heightmarch/error.hpp"
#include "io/json_writer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

TEST(Printable, EscapesWhatATerminalActsOn) {
  EXPECT_EQ(printable("plain text, ümlaut, 深さ"), "plain text, ümlaut, 深さ");
  EXPECT_EQ(printable(std::string("a\x1b[31mred\nb\0c\x7f", 14)), "a\\x1b[31mred\\x0ab\\x00c\\x7f");
  EXPECT_EQ(printable("\xc2\x9b"
                      "2J"),
            "\\xc2\\x9b2J");  // a C1 control (8-bit CSI) as UTF-8
  EXPECT_EQ(printable("\xe2\x80\xae"
                      "txt.exe"),
            "\\xe2\\x80\\xaetxt.exe");             // a right-to-left override
  EXPECT_EQ(printable("\xff\xc3"), "\\xff\\xc3");  // no UTF-8 character: a stray byte, a cut one
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");  // an overlong '/'
  const std::string once = printable(std::string("\x01\xc2\x85 x\xe2\x81\xa6", 9));
  EXPECT_EQ(printable(once), once);  // twice changes nothing
  EXPECT_STREQ(InputError("bad\x1b]0;title\x07").what(), "bad\\x1b]0;title\\x07");
}

// No raw control byte reaches the terminal, whichever input carried it.
TEST(Printable, CliErrorLinesQuoteInputEscaped) {
  const std::string dir = test::temp_dir("printable");
  const std::string escape = "$'\\x1b[2J\\x1b]0;pwned\\x07'";
  const std::string rays = dir + "/rays.csv";
  std::ofstream(rays) << "tx,ty,vx,vy,vz\n0.5,\x1b[31m,0,0,1\n";
  for (const std::string& args :
       {"trace --heightmap " + dir + "/" + escape + ".png", "trace --layers " + escape,
        "trace --technique " + escape, "trace --rays " + rays, "trace --view " + escape, escape}) {
    const auto r = test::run_command("bash -c \"" + std::string(HEIGHTMARCH_CLI) + " " + args + "\"");
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << args << ": " << r.output;
    EXPECT_EQ(r.output.find('\x07'), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find("\\x1b"), std::string::npos) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": " << r.output;
  }
}

// An error line longer than kMaxErrorLine keeps its head and its tail (what is wrong) around a note
// of what was cut, counted in characters, never splitting a character or an escape; once is enough.
TEST(Printable, ErrorLinesAreCutInTheirMiddle) {
  EXPECT_EQ(error_line("short \x1b"), "short \\x1b");
  const std::string long_text = "--gl-device '" + std::string(3000, '\x1b') + "\xe6\xb7\xb1" +
                                std::string(6000, 'D') + "': not a device";
  const std::string line = error_line(long_text);
  EXPECT_LE(line.size(), kMaxErrorLine + 40) << line;
  EXPECT_EQ(line.rfind("--gl-device '\\x1b", 0), 0u) << line;
  EXPECT_EQ(line.substr(line.size() - 16), "D': not a device") << line;
  const std::size_t cut = line.find("...[");
  ASSERT_NE(cut, std::string::npos) << line;
  EXPECT_EQ((cut - 13) % 4, 0u) << "an escape was split: " << line;
  const std::size_t count = std::stoul(line.substr(cut + 4));
  const std::string tail = line.substr(line.find("]...") + 4);
  EXPECT_EQ(count + (cut - 13) / 4 + (tail.size() - 15), 3000u + 1 + 6000) << "the count of what was cut";
  EXPECT_EQ(error_line(line), line);
  EXPECT_EQ(InputError(long_text).what(), line);
}

// Every option and input file name a user gives, at 10 KB, is echoed in one line of at most about
// kMaxErrorLine bytes that still says what is wrong.
TEST(Printable, LongEchoedValuesAreCut) {
  const std::string dir = test::temp_dir("long-values");
  const std::string long_name(10240, 'D');
  for (const auto& [args, why] : std::vector<std::pair<std::string, std::string>>{
           {"glsl --size 8x8 --gl egl --gl-device " + long_name, "not a device"},
           {"trace --size 8x8 --layers " + long_name, "layer"},
           {"trace --size 8x8 --technique " + long_name, "technique"},
           {"trace --views " + dir + "/" + long_name + ".csv", "File name too long"},
           {"trace --size 8x8 --heightmap " + long_name + ".png", "File name too long"},
           {"suite --dry-run --quick --techniques " + long_name, "technique"},
           {"recommend " + long_name, "File name too long"}}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.status, 2) << args.substr(0, 40) << ": " << r.output.substr(0, 300);
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args.substr(0, 40);
    EXPECT_LE(r.output.size(), kMaxErrorLine + 80) << args.substr(0, 40) << ": " << r.output.substr(0, 300);
    EXPECT_NE(r.output.find("characters cut]"), std::string::npos) << r.output.substr(0, 300);
    EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
  }
}

// A JSON string carries the text back exactly, and none of what a terminal acts on raw: controls,
// C1 controls and bidirectional overrides as \u escapes; a byte of no UTF-8 character as \xNN text.
TEST(Printable, JsonStringsEscapeWhatPrintableEscapes) {
  EXPECT_EQ(JsonWriter::quote("a\"b\\ ümlaut"), "\"a\\\"b\\\\ ümlaut\"");
  EXPECT_EQ(JsonWriter::quote("\x1b]0;\x07"), "\"\\u001b]0;\\u0007\"");
  EXPECT_EQ(JsonWriter::quote("\xc2\x9b"
                              "2J \xe2\x80\xae"
                              "x"),
            "\"\\u009b2J \\u202ex\"");
  EXPECT_EQ(JsonWriter::quote("\xff"), "\"\\\\xff\"");  // valid UTF-8, as JSON must be
}

// What the tool prints on success names the user's files too: a map or shader named with escapes
// is shown as text in trace's and glsl's summaries and in suite's plan.
TEST(Printable, SummariesShowFileNamesAsText) {
  const std::string dir = test::temp_dir("printable-names");
  const std::string escape = "$'\\x1b[2J\\x1b]0;pwned\\x07'";
  std::ofstream(dir + "/depth.pfm", std::ios::binary) << std::string("Pf\n1 1\n-1.0\n\0\0\0?", 16);  // 0.5
  std::ofstream(dir + "/mine.glsl")
      << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { return texCoords; }\n";
  const std::string map = dir + "/map" + escape + ".pfm";
  const std::string shader = dir + "/shader" + escape + ".glsl";
  ASSERT_EQ(test::run_command("bash -c \"cp " + dir + "/depth.pfm " + map + " && cp " + dir + "/mine.glsl " +
                              shader + "\"")
                .status,
            0);
  for (const std::string& args :
       {"trace --size 8x8 --repetitions 1 --heightmap " + map,
        "suite --dry-run --quick --no-glsl --techniques pom --heightmap " + map,
        "glsl --size 8x8 --repetitions 1 --layers 8 --heightmap " + map + " --shader " + shader}) {
    const auto r = test::run_command("bash -c \"" + std::string(HEIGHTMARCH_CLI) + " " + args + "\"");
    EXPECT_EQ(r.status, 0) << args << ": " << r.output;
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << args << ": " << r.output;
    EXPECT_NE(r.output.find("map\\x1b[2J\\x1b]0;pwned\\x07.pfm"), std::string::npos)
        << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace heightmarch
