// The GLSL worker as an untrusted process under limits: its message reader refuses what is no
// message before it allocates and checks every field of a request with the command line's checks;
// the worker says so and exits on a broken stream, answers a bad request and stays usable; and a
// brought-in shader that runs away while it compiles is stopped by the worker's memory limit and
// named in one line.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <thread>

#include "glsl/hit_outputs.hpp"
#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"
#include "test_support.hpp"
#include "util/sanitizers.hpp"

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;

std::string header(Message type, std::uint64_t size, std::uint32_t magic = protocol::kMagic) {
  protocol::Header h;
  h.magic = magic;
  h.type = type;
  h.size = size;
  return std::string(reinterpret_cast<const char*>(&h), sizeof h);
}

std::string message(Message type, const protocol::Writer& payload) {
  return header(type, payload.bytes().size()) + std::string(payload.bytes().begin(), payload.bytes().end());
}

// What a socket pair's reader gets of `bytes`, the writing end closed after them.
struct Received {
  std::optional<Message> type;
  std::string error;  // the exception's type and text, if one was thrown
  std::size_t capacity = 0;
};
Received receive_bytes(const std::string& bytes, std::uint64_t max_payload) {
  int fds[2];
  EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
  EXPECT_EQ(::write(fds[1], bytes.data(), bytes.size()), ssize_t(bytes.size()));
  ::close(fds[1]);
  Received r;
  std::vector<char> payload;
  try {
    r.type = protocol::receive(fds[0], payload, std::nullopt, max_payload);
  } catch (const protocol::ChannelClosed& e) {
    r.error = std::string("ChannelClosed: ") + e.what();
  } catch (const protocol::BadMessage& e) {
    r.error = std::string("BadMessage: ") + e.what();
  }
  ::close(fds[0]);
  r.capacity = payload.capacity();
  return r;
}

// Every output of the hit list crosses the socket and comes back out of the harness's attachments
// under its own name: each array carries its own values here, so a swapped or dropped one shows.
TEST(GlslProtocol, HitsCarryEveryOutputOfTheList) {
  HitBuffers hits;
  hits.resize(5);
  int channel = 0;
  hits.for_each([&](HitChannel, auto& values) {
    ++channel;
    using T = typename std::decay_t<decltype(values)>::value_type;
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = T(channel * 10 + int(i));
  });
  protocol::Writer writer;
  protocol::write(writer, hits);
  HitBuffers back;
  protocol::Reader reader(writer.bytes());
  protocol::read(reader, back, 5);
  reader.finish();
  HitBuffers::for_each_pair(
      hits, back, [](HitChannel c, const auto& a, const auto& b) { EXPECT_EQ(a, b) << info(c).name; });
  protocol::Reader short_reader(writer.bytes());
  EXPECT_THROW(protocol::read(short_reader, back, 4), protocol::BadMessage);

  // The harness draws every output a technique writes, four floats to an attachment, in the
  // list's order; the read-back puts each where it belongs and derives `discarded` from the uv.
  const std::string glsl = hit_outputs_glsl();
  std::vector<std::vector<float>> attachments(std::size_t(hit_output_attachments()),
                                              std::vector<float>(4 * 2, 0.0f));
  std::size_t k = 0;
  for (const HitChannelInfo& c : hit_channels()) {
    if (c.writer != ChannelWriter::hit && c.writer != ChannelWriter::optional) continue;
    EXPECT_NE(glsl.find("  float " + std::string(c.name) + ";\n"), std::string::npos) << c.name;
    for (std::size_t ray = 0; ray < 2; ++ray)
      attachments[k / 4][4 * ray + k % 4] = float(100 * (k + 1) + ray);
    ++k;
  }
  EXPECT_EQ(std::size_t(hit_output_attachments()), (k + 3) / 4);
  HitBuffers drawn;
  bool samples_known = false;
  read_hit_outputs(attachments, 2, true, drawn, samples_known);
  EXPECT_TRUE(samples_known);
  EXPECT_EQ(drawn.u, (std::vector<float>{100.0f, 101.0f}));
  EXPECT_EQ(drawn.v, (std::vector<float>{200.0f, 201.0f}));
  EXPECT_EQ(drawn.depth, (std::vector<float>{300.0f, 301.0f}));
  EXPECT_EQ(drawn.samples, (std::vector<std::uint32_t>{400, 401}));
  EXPECT_EQ(drawn.shadow, (std::vector<float>{500.0f, 501.0f}));
  EXPECT_EQ(drawn.discarded, (std::vector<std::uint8_t>{1, 1}));  // uv outside [0,1]^2
  const auto [attachment, component] = samples_output();
  attachments[std::size_t(attachment)][std::size_t(component)] = -1.0f;  // a brought-in shader's
  read_hit_outputs(attachments, 2, false, drawn, samples_known);
  EXPECT_FALSE(samples_known);
  EXPECT_EQ(drawn.samples[0], 0u);
  EXPECT_EQ(drawn.discarded, (std::vector<std::uint8_t>{0, 0}));
}

TEST(GlslProtocol, ReceiveRefusesWhatIsNoMessageBeforeItAllocates) {
  EXPECT_EQ(receive_bytes("", 1 << 20).error, "ChannelClosed: channel closed");
  EXPECT_EQ(receive_bytes(header(Message::draw, 0).substr(0, 9), 1 << 20).error,
            "BadMessage: the channel closed inside a message header");
  EXPECT_EQ(receive_bytes(header(Message::draw, 0, 0xdeadbeef), 1 << 20).error,
            "BadMessage: bytes that are no message (magic 0xdeadbeef)");
  EXPECT_EQ(receive_bytes(header(Message(77), 0), 1 << 20).error, "BadMessage: a message of unknown type 77");
  const auto over = receive_bytes(header(Message::prepare, std::uint64_t(4) << 30), std::uint64_t(1) << 30);
  EXPECT_EQ(over.error,
            "BadMessage: a message of 4294967296 bytes, more than the 1073741824 its reader's memory budget "
            "leaves");
  EXPECT_EQ(over.capacity, 0u);
  // Within the budget, a header that claims 4 GiB costs the bytes that came, not 4 GiB.
  const auto claimed =
      receive_bytes(header(Message::prepare, std::uint64_t(4) << 30) + "0123456789", std::uint64_t(1) << 40);
  EXPECT_EQ(claimed.error, "BadMessage: the channel closed after 10 of a message's 4294967296 bytes");
  EXPECT_LE(claimed.capacity, std::size_t(1) << 20);
  const auto fine = receive_bytes(header(Message::draw, 0), 0);  // small messages are always read
  EXPECT_EQ(fine.type, Message::draw) << fine.error;
}

// A prepare's payload as the client writes it, with the fields a test breaks.
protocol::Writer prepare_payload(const TechniqueParams& params, const DepthMap& map, const DrawnRays& rays,
                                 std::uint8_t map_flag = 1, const std::string& shader = "") {
  protocol::Writer w;
  protocol::write(w, params);
  w.value(map_flag);
  protocol::write(w, map);
  w.value(std::uint8_t(1));
  protocol::write(w, rays);
  w.text(shader);
  return w;
}

TEST(GlslProtocol, ReadRequestChecksEveryFieldAsTheCommandLineDoes) {
  TechniqueParams good;
  good.refine = 5;  // so write() never asks the registry about a broken technique
  const DepthMap map{4, 4, std::vector<float>(16, 0.5f)};
  const DrawnRays rays = screen_layout(make_ray_list({0.5f}, {0.5f}, {0.0f}, {0.0f}, {1.0f})).drawn;
  const auto read = [&](const protocol::Writer& payload) {
    try {
      protocol::read_request(Message::prepare, payload.bytes());
      return std::string("ok");
    } catch (const InputError& e) {
      return std::string("InputError: ") + e.what();
    } catch (const protocol::BadMessage& e) {
      return std::string("BadMessage: ") + e.what();
    }
  };
  EXPECT_EQ(read(prepare_payload(good, map, rays)), "ok");
  TechniqueParams p = good;
  p.technique = Technique(100000000);
  EXPECT_EQ(read(prepare_payload(p, map, rays)), "InputError: technique 100000000 is not one of the " +
                                                     std::to_string(kTechniqueCount) + " of the registry");
  p = good;
  p.layers = {std::nanf(""), std::nanf("")};
  EXPECT_NE(read(prepare_payload(p, map, rays)).find("InputError: layers nan-nan"), std::string::npos);
  p = good;
  p.wrap = Wrap(7);
  EXPECT_EQ(read(prepare_payload(p, map, rays)), "InputError: wrap mode 7 is neither repeat nor clamp");
  EXPECT_NE(read(prepare_payload(good, DepthMap{0, 0, {}}, rays)).find("a depth map of 0x0 texels"),
            std::string::npos);
  DepthMap nan_map = map;
  nan_map.texels[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(read(prepare_payload(good, nan_map, rays)).find("1 NaN/Inf texels (first at 1,1)"),
            std::string::npos);
  DrawnRays below = rays;
  below.rays.vz[0] = -1.0f;
  EXPECT_NE(read(prepare_payload(good, map, below)).find("InputError: ray 1 of the batch"),
            std::string::npos);
  DrawnRays turned = rays;
  turned.turn_u[3] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(read(prepare_payload(good, map, turned)),
            "InputError: drawn ray 4: turns not finite within 1e6, or a flag not 0 or 1");
  DrawnRays flagged = rays;
  flagged.drawn[0] = 2;
  EXPECT_EQ(read(prepare_payload(good, map, flagged)),
            "InputError: drawn ray 1: turns not finite within 1e6, or a flag not 0 or 1");
  DrawnRays ragged = rays;
  ragged.row_width = 1000;
  EXPECT_EQ(read(prepare_payload(good, map, ragged)),
            "InputError: drawn rays of 1024 texels in rows of 1000");
  ragged.row_width = 0;
  EXPECT_EQ(read(prepare_payload(good, map, ragged)), "InputError: drawn rays of 1024 texels in rows of 0");
  EXPECT_EQ(read(prepare_payload(good, map, rays, 2)), "BadMessage: map flag 2 is not 0 or 1");
  protocol::Writer short_payload = prepare_payload(good, map, rays);
  std::vector<char> cut(short_payload.bytes().begin(), short_payload.bytes().end() - 3);
  EXPECT_THROW(protocol::read_request(Message::prepare, cut), protocol::BadMessage);
  EXPECT_THROW(protocol::read_request(Message::hits, {}), protocol::BadMessage);
}

// The worker run by hand on a stream: what it answers on stdout and says on stderr, and its exit.
struct WorkerRun {
  int status = -1;
  std::string answers, errors;
  double peak_mib = 0;
};
WorkerRun run_worker(const std::string& stream, const std::string& memory_limit) {
  const std::string dir = test::temp_dir("worker-stream");
  std::ofstream(dir + "/in", std::ios::binary) << stream;
  const std::string worker = test::glsl_worker();
  const auto r = test::run_with_peak(worker + " --threads 1 --memory-limit " + memory_limit + " < " + dir +
                                     "/in > " + dir + "/out 2> " + dir + "/err");
  std::ifstream out(dir + "/out", std::ios::binary), err(dir + "/err");
  return {r.status, std::string((std::istreambuf_iterator<char>(out)), {}),
          std::string((std::istreambuf_iterator<char>(err)), {}), r.peak_mib};
}

TEST(GlslWorker, SaysWhatIsWrongWithItsStreamAndExits) {
  const auto magic = run_worker(header(Message::draw, 0, 0xdeadbeef), "1G");
  EXPECT_EQ(magic.status, 1);
  EXPECT_EQ(magic.errors,
            "heightmarch-glsl-worker: a malformed message from its client: bytes that are no message (magic "
            "0xdeadbeef); the channel is lost\n");
  const auto cut = run_worker(header(Message::prepare, 100) + "0123456789", "1G");
  EXPECT_EQ(cut.status, 1);
  EXPECT_NE(cut.errors.find("the channel closed after 10 of a message's 100 bytes"), std::string::npos)
      << cut.errors;
  const auto claimed = run_worker(header(Message::prepare, std::uint64_t(4) << 30), "64G");
  EXPECT_EQ(claimed.status, 1);
  EXPECT_NE(claimed.errors.find("after 0 of a message's 4294967296 bytes"), std::string::npos)
      << claimed.errors;
  // Not the 4 GiB claimed: the worker's own peak (llvmpipe's start-up; doubled by ASan's shadow).
  EXPECT_LT(claimed.peak_mib, kAddressSanitizer ? 1024.0 : 512.0);
  // A bad request is answered and the worker serves the next: a draw after a refused prepare.
  TechniqueParams broken;
  broken.refine = 5;
  broken.technique = Technique(100000000);
  const auto answered = run_worker(
      message(Message::prepare,
              prepare_payload(broken, DepthMap{4, 4, std::vector<float>(16, 0.5f)},
                              screen_layout(make_ray_list({0.5f}, {0.5f}, {0.0f}, {0.0f}, {1.0f})).drawn)) +
          header(Message::read, 0),
      "1G");
  EXPECT_EQ(answered.status, 0) << answered.errors;
  EXPECT_NE(answered.answers.find("technique 100000000 is not one of the"), std::string::npos);
}

// A worker started without a parent-death signal (as from a thread other than its client's main
// one) still ends when its client hangs up, in the middle of a draw: it watches its channel.
TEST(GlslWorker, EndsWhenItsClientHangsUpEvenWhileDrawing) {
  const std::string dir = test::temp_dir("hang-up");
  std::ofstream(dir + "/endless.glsl")
      << "vec2 ParallaxMapping(vec2 t, vec3 v) {\n"
         "  while (texture(depthMap, t).r < 2.0) t += vec2(1e-7);\n  return t;\n}\n";
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
  const std::string worker = test::glsl_worker();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(fds[1], STDIN_FILENO);
    ::dup2(fds[1], STDOUT_FILENO);
    ::close(fds[0]);
    ::execl(worker.c_str(), worker.c_str(), "--threads", "1", "--memory-limit", "1G",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(fds[1]);
  std::vector<char> reply;
  ASSERT_EQ(protocol::receive(fds[0], reply, std::nullopt, 1 << 20), Message::ready);
  const std::string request =
      message(Message::prepare, prepare_payload(TechniqueParams(), make_builtin_heightfield("bricks", 64, 1),
                                                screen_layout(make_view_rays(default_view(256, 256))).drawn,
                                                1, dir + "/endless.glsl")) +
      header(Message::draw, 0);
  ASSERT_EQ(::write(fds[0], request.data(), request.size()), ssize_t(request.size()));
  ASSERT_EQ(protocol::receive(fds[0], reply, std::nullopt, 1 << 20), Message::compiled);
  ASSERT_EQ(protocol::receive(fds[0], reply, std::nullopt, 1 << 20), Message::done);
  std::this_thread::sleep_for(
      std::chrono::seconds(1));  // drawing: llvmpipe cuts this loop only after minutes
  const auto closed = std::chrono::steady_clock::now();
  ::close(fds[0]);
  int status = 0;
  // Polls every 50 ms for the worker's exit, for 5 s at most.
  while (::waitpid(pid, &status, WNOHANG) == 0 &&
         std::chrono::steady_clock::now() - closed < std::chrono::seconds(5))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const bool ended = ::waitpid(pid, &status, WNOHANG) != 0 || ::kill(pid, 0) != 0;
  if (!ended) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
  }
  EXPECT_TRUE(ended) << "the worker drew on for 5 s after its client hung up";
}

// What the tool holds before any input, in MiB, as it says when refusing a budget of 1 byte.
double footprint_mib() {
  const auto r = test::run_cli("trace --memory-limit 1");
  std::smatch m;
  return std::regex_search(r.output, m, std::regex("own footprint of ([0-9.]+) MiB")) ? std::stod(m[1]) : 0.0;
}

// A shader whose preprocessor grows without end (nested #defines), or that declares a 1.6 GB
// array, is stopped by the worker's memory limit within seconds and named in one line; neither
// process grows past the budget (the worker by at most the stacks it reserved before its limit).
TEST(GlslWorker, RunawayShadersStopAtTheMemoryLimit) {
  if (kAddressSanitizer)
    GTEST_SKIP() << "an AddressSanitizer build runs the worker without its OS data limit";
  const std::string dir = test::temp_dir("runaway");
  {
    std::ofstream bomb(dir + "/bomb.glsl");
    bomb << "#define A0 1.0\n";
    for (int i = 1; i <= 40; ++i) bomb << "#define A" << i << " (A" << i - 1 << "+A" << i - 1 << ")\n";
    bomb << "vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) { return texCoords * A40; }\n";
    std::ofstream(dir + "/array.glsl") << "vec2 ParallaxMapping(vec2 t, vec3 v) { float a[400000000]; a[1] = "
                                          "t.x; return vec2(a[1], t.y); }\n";
  }
  const int limit = int(footprint_mib()) + 64;
  for (const char* shader : {"bomb.glsl", "array.glsl"}) {
    const auto r = test::run_with_peak(std::string(HEIGHTMARCH_CLI) +
                                       " glsl --size 8x8 --repetitions 1 --threads 1 --shader " + dir + "/" +
                                       shader + " --memory-limit " + std::to_string(limit) + "M");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(std::string(shader) + ": the GLSL worker "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("during its compile"), std::string::npos) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_LE(r.peak_mib, limit + 16) << r.output;
  }
}

}  // namespace
}  // namespace heightmarch
