// GlslRunner as a client of heightmarch-glsl-worker (src/glsl/worker_main.cpp): one worker
// process per llvmpipe thread count, spoken to over a socket pair (src/glsl/protocol.hpp).
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <tbb/info.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/glsl_runner.hpp"

extern char** environ;

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;

constexpr auto kRequestTimeout = std::chrono::seconds(600);  // a 16k x 16k draw at one thread fits
constexpr auto kExitGrace = std::chrono::seconds(5);  // for a worker told to stop, or closing after EOF

std::string worker_path() {
  if (const char* path = std::getenv("HEIGHTMARCH_GLSL_WORKER"); path && *path) return path;
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot find the GLSL worker: /proc/self/exe: " + error.message());
  return (self.parent_path() / "heightmarch-glsl-worker").string();
}

// Bit for bit, so a NaN or a -0 that changed is sent again.
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

// The arrays of a batch the worker reads (protocol::write(RayBatch) sends these).
std::array<const std::vector<float>*, 5> ray_arrays(const RayBatch& rays) {
  return {&rays.tx, &rays.ty, &rays.vx, &rays.vy, &rays.vz};
}

std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status))
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
           ")";
  return "was stopped";
}

}  // namespace

struct GlslRunner::Worker {
  std::string name;  // "GLSL worker PATH (N threads)", for every error
  pid_t pid = -1;
  int fd = -1;
  std::string failure;  // why the worker is gone; empty while it runs
  // Copies of the depth map and rays the worker holds, as last sent (none: unknown, send them):
  // the suite prepares every configuration on the same scene, and these are 20+ MB at 1024x1024.
  // Contents, not pointers, decide: a caller's buffer may be refilled in place or reused.
  std::optional<DepthMap> sent_map;
  std::optional<std::array<std::vector<float>, 5>> sent_rays;

  bool holds(const DepthMap& map) const {
    return sent_map && sent_map->width == map.width && sent_map->height == map.height &&
           same_bits(sent_map->texels, map.texels);
  }
  bool holds(const RayBatch& rays) const {
    if (!sent_rays) return false;
    const auto arrays = ray_arrays(rays);
    for (std::size_t i = 0; i < arrays.size(); ++i)
      if (!same_bits((*sent_rays)[i], *arrays[i])) return false;
    return true;
  }

  // Waits for the worker to exit, up to kExitGrace, then kills it; returns how it ended.
  std::string reap() {
    if (pid < 0) return "already reaped";
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + kExitGrace;
    pid_t done = 0;
    // Polls every 10 ms until the deadline.
    while ((done = ::waitpid(pid, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (done == 0) {
      ::kill(pid, SIGKILL);
      done = ::waitpid(pid, &status, 0);
    }
    pid = -1;
    return done < 0 ? std::string("was lost (") + std::strerror(errno) + ")" : describe_status(status);
  }

  void close_channel() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }

  // Sends the request (none: only reads the worker's greeting) and hands the answer, which must be
  // of type `answer`, to `parse`. The worker's errors come back as they were thrown there (its
  // other errors named after it); losing the worker or a garbled answer is a runtime_error.
  void call(std::optional<Message> request, const protocol::Writer& payload, Message answer, const char* what,
            const std::function<void(protocol::Reader&)>& parse) {
    if (!failure.empty()) throw std::runtime_error(name + " is gone (" + failure + ")");
    Message type = Message::error;
    std::string text;
    try {
      const auto deadline = std::chrono::steady_clock::now() + kRequestTimeout;
      if (request) protocol::send(fd, *request, payload, deadline);
      std::vector<char> reply;
      type = protocol::receive(fd, reply, deadline);
      protocol::Reader reader(reply);
      if (type == answer) {
        parse(reader);
        reader.finish();
        return;
      }
      if (type == Message::input_error || type == Message::error) {
        reader.text(text);
        reader.finish();
      }
    } catch (const protocol::ChannelTimeout&) {
      const std::string seconds = std::to_string(kRequestTimeout.count());
      fail("no answer to " + std::string(what) + " within " + seconds + " s; killed", true);
    } catch (const protocol::ChannelClosed& e) {
      fail(std::string(e.what()) + " during " + what, false);
    }
    if (type == Message::input_error) throw InputError(text);
    if (type == Message::error) throw std::runtime_error(name + ": " + text);
    const std::string received = std::to_string(unsigned(type));
    fail("answered " + std::string(what) + " with message type " + received + "; killed", true);
  }

  // Ends the worker (killed, or reaped after it closed the channel) and throws; the runner's later
  // calls throw too.
  [[noreturn]] void fail(const std::string& why, bool kill) {
    if (kill && pid > 0) ::kill(pid, SIGKILL);
    close_channel();
    const std::string end = reap();
    failure = kill ? why : why + "; the worker " + end;
    throw std::runtime_error(name + ": " + failure);
  }

  ~Worker() {
    close_channel();  // EOF on its stdin: the worker destroys its context and exits
    reap();
  }
};

GlslRunner& GlslRunner::instance(int threads) {
  const int wanted = threads > 0 ? threads : tbb::info::default_concurrency();
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<GlslRunner>> runners;  // workers stop when these are destroyed at exit
  const std::lock_guard lock(mutex);
  std::unique_ptr<GlslRunner>& runner = runners[wanted];
  if (!runner) runner.reset(new GlslRunner(wanted));
  return *runner;
}

GlslRunner::GlslRunner(int threads) : worker_(std::make_unique<Worker>()), threads_(threads) {
  Worker& w = *worker_;
  const std::string path = worker_path();
  w.name = "GLSL worker " + path + " (" + std::to_string(threads) + (threads == 1 ? " thread)" : " threads)");
  int fds[2];
  // Close-on-exec: no other child (another worker, a popen) keeps this worker's channel open.
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw std::runtime_error(w.name + ": socketpair: " + std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  const std::string thread_text = std::to_string(threads);
  char* argv[] = {const_cast<char*>(path.c_str()), const_cast<char*>("--threads"),
                  const_cast<char*>(thread_text.c_str()), nullptr};
  const int spawned = ::posix_spawn(&w.pid, path.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  w.fd = fds[0];
  if (spawned != 0) {
    w.pid = -1;
    w.close_channel();
    throw std::runtime_error(w.name + ": cannot start: " + std::strerror(spawned) +
                             " (build the heightmarch-glsl-worker target, or set HEIGHTMARCH_GLSL_WORKER)");
  }
  std::uint32_t protocol_version = 0;
  w.call(std::nullopt, {}, Message::ready, "start-up", [&](protocol::Reader& reader) {
    reader.value(protocol_version);
    reader.text(renderer_);
    reader.text(version_);
  });
  if (protocol_version != protocol::kVersion)
    w.fail("speaks protocol " + std::to_string(protocol_version) + ", this build " +
               std::to_string(protocol::kVersion) + " (a stale build?); killed",
           true);
}

GlslRunner::~GlslRunner() = default;

void GlslRunner::prepare(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
                         const std::string& shader_path) {
  Worker& w = *worker_;
  const bool send_map = !w.holds(map), send_rays = !w.holds(rays);
  protocol::Writer request;
  protocol::write(request, params);
  request.value(std::uint8_t(send_map));
  if (send_map) protocol::write(request, map);
  request.value(std::uint8_t(send_rays));
  if (send_rays) protocol::write(request, rays);
  request.text(shader_path);
  try {
    w.call(Message::prepare, request, Message::done, "prepare", [](protocol::Reader&) {});
  } catch (...) {
    // A prepare that failed may have replaced either or neither: the next one sends both.
    w.sent_map.reset();
    w.sent_rays.reset();
    throw;
  }
  if (send_map) w.sent_map = map;
  if (send_rays) w.sent_rays = {rays.tx, rays.ty, rays.vx, rays.vy, rays.vz};
}

double GlslRunner::draw() {
  double seconds = 0.0;
  worker_->call(Message::draw, {}, Message::drawn, "draw",
                [&](protocol::Reader& reader) { reader.value(seconds); });
  return seconds;
}

void GlslRunner::read(HitBuffers& hits, bool& samples_known) const {
  std::uint8_t known = 0;
  worker_->call(Message::read, {}, Message::hits, "read", [&](protocol::Reader& reader) {
    protocol::read(reader, hits);
    reader.value(known);
  });
  samples_known = known != 0;
}

}  // namespace heightmarch
