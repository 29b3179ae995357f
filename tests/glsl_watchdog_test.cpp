// The GLSL watchdog: a brought-in shader whose loop runs on is killed at the draw's bound with an
// InputError, and the runner's next prepare starts a new worker that draws as before; a worker
// that hangs at start-up, in its uploads or before its read-back is noticed at that step's own
// bound; and a worker dies with its client.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"
#include "util/sanitizers.hpp"

namespace heightmarch {
namespace {

// At 256x256 rays and one llvmpipe thread this loop (cut by llvmpipe at 65,535 passes) takes
// about 50 s on an AMD EPYC; its bound is 10.5 s.
constexpr const char* kEndless = R"(vec2 ParallaxMapping(vec2 texCoords, vec3 viewDir) {
  vec2 t = texCoords;
  while (texture(depthMap, t).r < 2.0) t += vec2(1e-7);
  return t;
}
)";

TEST(GlslWatchdog, KillsAnEndlessDrawAndRestarts) {
  const std::string path = test::temp_dir("watchdog") + "/endless.glsl";
  std::ofstream(path) << kEndless;
  const DepthMap map = make_builtin_heightfield("bricks", 64, 1);
  const RayBatch rays = make_view_rays(default_view(256, 256));
  TechniqueParams params;
  GlslRunner& runner = GlslRunner::instance(1);
  runner.prepare(map, params, rays, path);
  try {
    runner.draw();
    FAIL() << "the endless draw returned";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("endless.glsl: the GLSL draw of 65536 rays ran past its bound of 10.5 s"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("restarts"), std::string::npos) << message;
  }
  // A new worker serves the next request as the first did.
  const RayBatch few = make_view_rays(default_view(32, 32));
  runner.prepare(map, params, few);
  runner.draw();
  HitBuffers glsl, reference;
  bool samples_known = false;
  runner.read(glsl, samples_known);
  Tracer(map, params, Isa::scalar).run(few, reference);
  ASSERT_EQ(glsl.size(), reference.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < few.size(); ++i) same += glsl.samples[i] == reference.samples[i];
  EXPECT_GT(same, few.size() * 9 / 10);
}

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// What a call threw (its message), or "returned", and how long it took.
struct Outcome {
  std::string message = "returned";
  double seconds = 0;
};
template <class Call>
Outcome outcome_of(Call call) {
  const Clock::time_point start = Clock::now();
  Outcome o;
  try {
    call();
  } catch (const std::exception& e) {
    o.message = e.what();
  }
  o.seconds = seconds_since(start);
  return o;
}

// A worker that hangs (HEIGHTMARCH_GLSL_WORKER_STALL: it stops itself) at start-up, in its
// uploads or before its read-back is noticed at that step's bound (20 s; 10 s and a little for the
// few bytes and rays here), not at a request timeout of minutes, and killed. One worker each, at
// thread counts of their own, through a script that tells each where to hang by its thread count;
// the three wait side by side.
TEST(GlslWatchdog, AWorkerThatHangsIsNoticedAtItsStepsBound) {
  if (kAddressSanitizer)
    GTEST_SKIP()
        << "20 s of waiting on the same bounds the Release build's run holds (the test command's time)";
  const std::string dir = test::temp_dir("stall");
  const std::string worker = test::glsl_worker();
  const std::string script = dir + "/stalling-worker";
  std::ofstream(script) << "#!/bin/sh\n"
                        << "case \"$2\" in 7) s=start-up ;; 8) s=upload ;; 9) s=read-back ;; *) s= ;; esac\n"
                        << "HEIGHTMARCH_GLSL_WORKER_STALL=$s exec " << worker << " \"$@\"\n";
  std::filesystem::permissions(script, std::filesystem::perms::owner_all);
  gl_paths_built();  // asked of the real worker, before the script stands in for it
  std::optional<test::ScopedEnv> stalling(std::in_place, "HEIGHTMARCH_GLSL_WORKER",
                                          script);  // read as each runner starts its worker
  GlslRunner& upload = GlslRunner::instance(8);
  GlslRunner& read_back = GlslRunner::instance(9);
  const DepthMap map = make_builtin_heightfield("bricks", 64, 1);
  const RayBatch rays = make_view_rays(default_view(32, 32));
  const TechniqueParams params;
  auto start_up =
      std::async(std::launch::async, [&] { return outcome_of([&] { GlslRunner::instance(7); }); });
  auto uploads =
      std::async(std::launch::async, [&] { return outcome_of([&] { upload.prepare(map, params, rays); }); });
  read_back.prepare(map, params, rays);
  read_back.draw();
  const Outcome read = outcome_of([&] {
    HitBuffers hits;
    bool samples_known = false;
    read_back.read(hits, samples_known);
  });
  const Outcome started = start_up.get(), uploaded = uploads.get();
  stalling.reset();
  EXPECT_NE(started.message.find("no answer to start-up within 20.0 s; killed"), std::string::npos)
      << started.message;
  EXPECT_GE(started.seconds, 20.0);
  EXPECT_LT(started.seconds, 25.0);
  for (const auto& [what, o] : {std::pair{"upload", uploaded}, std::pair{"read-back", read}}) {
    EXPECT_NE(o.message.find(std::string("no answer to ") + what + " within 10.0 s; killed"),
              std::string::npos)
        << o.message;
    EXPECT_GE(o.seconds, 10.0) << what;
    EXPECT_LT(o.seconds, 15.0) << what;
  }
}

// The pid of the running GLSL worker (its draw loop, not a worker asked one question) that
// `parent` started, or -1.
pid_t worker_of(pid_t parent) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    std::ifstream stat(entry.path() / "stat");
    std::string pid, name, state;
    pid_t ppid = 0;
    if (!(stat >> pid >> name >> state >> ppid) || ppid != parent || name != "(heightmarch-gls)") continue;
    std::ifstream cmdline(entry.path() / "cmdline");
    const std::string args((std::istreambuf_iterator<char>(cmdline)), {});
    if (args.find("--threads") != std::string::npos) return pid_t(std::stol(pid));
  }
  return -1;
}

// Whether a process runs (a zombie, dead but not yet reaped by whoever adopted it, does not).
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string id, name, state;
  return stat >> id >> name >> state && state != "Z";
}

// The client killed (SIGKILL: nothing of it runs to clean up) while its worker draws an endless
// loop: the worker dies with it (its parent-death signal), not drawing on alone as an orphan.
TEST(GlslWatchdog, AWorkerDiesWithItsKilledClient) {
  const std::string path = test::temp_dir("orphan") + "/endless.glsl";
  std::ofstream(path) << kEndless;
  const pid_t client = ::fork();
  if (client == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    ::execl(HEIGHTMARCH_CLI, "heightmarch", "glsl", "--shader", path.c_str(), "--res", "64", "--size",
            "256x256", "--threads", "1", "--repetitions", "1", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  pid_t worker = -1;
  const Clock::time_point start = Clock::now();
  // Polls every 50 ms for the worker, for 20 s at most.
  while ((worker = worker_of(client)) < 0 && seconds_since(start) < 20.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_GT(worker, 0) << "the client started no worker";
  std::this_thread::sleep_for(std::chrono::seconds(2));  // compiled, and drawing
  ASSERT_TRUE(running(worker));
  ::kill(client, SIGKILL);
  ::waitpid(client, nullptr, 0);
  const Clock::time_point killed = Clock::now();
  // Polls every 50 ms for the worker's end, for 5 s at most.
  while (running(worker) && seconds_since(killed) < 5.0)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const bool orphan = running(worker);
  if (orphan) ::kill(worker, SIGKILL);
  EXPECT_FALSE(orphan) << "the worker drew on for 5 s after its client was killed";
}

}  // namespace
}  // namespace heightmarch
