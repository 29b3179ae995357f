// GlslRunner as a client of heightmarch-glsl-worker (src/glsl/worker_main.cpp): one worker
// process per GL target and llvmpipe thread count, spoken to over a socket pair
// (src/glsl/protocol.hpp); every wait on it bounded by its step's own deadline.
#include "heightmarch/glsl_runner.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>
#include <type_traits>
#include <vector>

#include "glsl/protocol.hpp"
#include "glsl/screen_layout.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "util/sanitizers.hpp"

extern char** environ;

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;
using Seconds = std::chrono::duration<double>;

// The steps' bounds (glsl_runner.hpp). Start-up: exec to ready, loading the GL libraries (libLLVM
// alone is 100 MB) and making the context, well under a second on an idle machine; also what
// --paths and each device of --list-devices may take.
constexpr Seconds kStartupTimeout{20.0};
constexpr auto kExitGrace = std::chrono::seconds(5);  // for a worker told to stop, or closing after EOF
// A program's compile and link, from the request sent to "compiled": the built-in techniques take
// well under a second on llvmpipe (their JIT comes at the first draw, within the draw's bound); a
// brought-in shader whose preprocessor or compiler runs away (nested #defines grow by some
// 170 MB/s) is killed here.
constexpr Seconds kCompileTimeout{20.0};
// The other steps: a floor, and what grows with the bytes moved or the texels built. Sending and
// uploading 20 ns a byte (50 MB/s, far below a socket's and a texture upload's speed); the
// precomputed textures 1 us a texel, or 50 us where the technique reads a cone map, whose build
// grows faster than the map (measured at load 20 on 2 cores: 24 s at 1024^2, 117 s at 2048^2);
// reading back 200 ns a ray (the 32 bytes of its hit and shadow, converted and sent).
constexpr double kStepFloorSeconds = 10.0;
constexpr double kSecondsPerByte = 20e-9;
constexpr double kSecondsPerTexel = 1e-6, kSecondsPerConeTexel = 50e-6;
constexpr double kReadSecondsPerRay = 200e-9;
// What an llvmpipe thread reserves of the worker's data (RLIMIT_DATA counts it) beyond what it
// touches: its stack and buffers, 16.6 MiB a thread measured (1 thread: 29 MiB of data, 16: 277 MiB,
// 59 MiB resident at either).
constexpr double kReservedBytesPerThread = 32.0 * 1024 * 1024;
// What a GPU's driver may map beyond that before its context exists (the worker lowers its limit to
// what it holds then plus the budget): NVIDIA's reserves large private ranges at start-up. An
// allowance, not a measured figure: no GPU was at hand (docs/reproducing.md says so).
constexpr double kGpuDriverBytes = 4.0 * 1024 * 1024 * 1024;

// The draw watchdog. The slowest built-in technique (shadow: a march and a shadow march) takes
// about 4 ns per sample at one llvmpipe thread on an AMD EPYC and at most 2 x max layers +
// refine steps + a few samples per ray. A draw may take 25 times that (100 ns per sample, at any
// thread count: the machine may be shared) plus 10 s for the first draw's JIT compile; a
// brought-in loop that runs on (llvmpipe cuts each loop at 65,535 passes, which at 1024x1024 still
// takes minutes) is killed at the bound.
constexpr double kDrawFloorSeconds = 10.0;
constexpr double kDrawSecondsPerSample = 100e-9;

double draw_bound_seconds(const TechniqueParams& params, std::size_t rays) {
  const double samples_per_ray = 2.0 * double(params.layers.max_layers) + double(params.refine_steps()) + 8.0;
  return kDrawFloorSeconds + double(rays) * samples_per_ray * kDrawSecondsPerSample;
}

double upload_bound_seconds(const TechniqueParams& params, std::size_t bytes, std::size_t texels,
                            const std::string& shader_path) {
  const bool cone = shader_path.empty() && has(info(params.technique).needs, Needs::cone_map);
  return kStepFloorSeconds + double(bytes) * kSecondsPerByte +
         double(texels) * (cone ? kSecondsPerConeTexel : kSecondsPerTexel);
}

std::string worker_path() {
  if (const char* path = std::getenv("HEIGHTMARCH_GLSL_WORKER"); path && *path) return path;
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot find the GLSL worker: /proc/self/exe: " + error.message());
  return (self.parent_path() / "heightmarch-glsl-worker").string();
}

// Bit for bit, so a NaN or a -0 that changed is sent again.
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status))
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
           ")";
  return "was stopped";
}

// A worker process: started, spoken to, ended.
struct WorkerProcess {
  WorkerProcess() = default;
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  std::string path;
  int threads = 1;
  GlTarget target;   // resolved: its path is known
  std::string name;  // "GLSL worker PATH (N threads)" or "(EGL, N threads)", for every error
  pid_t pid = -1;
  int fd = -1;
  std::string failure;           // why the last worker is gone; empty while one runs
  std::size_t memory_limit = 0;  // the budget it was given when it started
  std::string how_it_ended;  // of the last worker: "exited with status 1", "was killed by signal 9 (Killed)"
  bool out_of_memory = false;  // the last worker exited for an allocation that failed
  GlRenderer renderer;
  // Copies of the depth map and rays the worker holds, as last sent (none: unknown, send them):
  // the suite prepares every configuration on the same scene, and these are 20+ MB at 1024x1024.
  // Contents, not pointers, decide: a caller's buffer may be refilled in place or reused.
  std::optional<DepthMap> sent_map;
  std::optional<std::array<std::vector<float>, protocol::kRayArrays>> sent_rays;
  std::vector<std::uint32_t> sent_origin;  // and their pixels, which the layout follows
  std::array<int, 4> sent_grid{};          // image and frame sizes
  // Where the draw put each ray of the batch last sent (screen_layout.hpp), for the read-back.
  std::vector<std::uint32_t> texel_of;
  // The last prepare that succeeded: what a draw is bounded by and whose fault a draw past it is.
  bool prepared = false;
  std::string shader_path;
  std::size_t rays = 0;  // texels drawn
  double draw_bound = kDrawFloorSeconds;

  bool holds(const DepthMap& map) const {
    return sent_map && sent_map->width == map.width && sent_map->height == map.height &&
           same_bits(sent_map->texels, map.texels);
  }
  static std::array<int, 4> grid(const RayBatch& rays) {
    return {rays.image_width, rays.image_height, rays.frame_width, rays.frame_height};
  }
  bool holds(const RayBatch& rays) const {
    if (!sent_rays || sent_origin != rays.origin || sent_grid != grid(rays)) return false;
    const auto arrays = protocol::ray_arrays(rays);
    for (std::size_t i = 0; i < arrays.size(); ++i)
      if (!same_bits((*sent_rays)[i], *arrays[i])) return false;
    return true;
  }

  // The worker's arguments for its draw loop.
  std::vector<std::string> arguments() const {
    std::vector<std::string> args = {"--threads",      std::to_string(threads),
                                     "--memory-limit", std::to_string(memory_budget()),
                                     "--gl",           to_string(*target.path)};
    if (!target.device.empty()) args.insert(args.end(), {"--gl-device", target.device});
    return args;
  }

  // Starts the worker with `args` under an OS memory limit (RLIMIT_DATA: what it may allocate;
  // RLIMIT_AS would also count the libraries' mappings, 400 MiB and more) of the budget and what
  // its threads and a GPU's driver reserve, which it lowers once its context exists
  // (worker_main.cpp); it dies with this process (PR_SET_PDEATHSIG, and it checks its parent is
  // still this one before it runs). Throws std::runtime_error when it cannot.
  void spawn(const std::vector<std::string>& args, bool gpu_driver) {
    failure.clear();
    int fds[2], exec_report[2];
    // Close-on-exec: no other child (another worker, a popen) keeps this worker's channel open.
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
      throw std::runtime_error(name + ": socketpair: " + std::strerror(errno));
    if (::pipe2(exec_report, O_CLOEXEC) != 0) {
      const int error = errno;
      ::close(fds[0]);
      ::close(fds[1]);
      throw std::runtime_error(name + ": pipe: " + std::strerror(error));
    }
    memory_limit = memory_budget();
    rlimit limit{};
    ::getrlimit(RLIMIT_DATA, &limit);
    const double data =
        double(memory_limit) + kReservedBytesPerThread * threads + (gpu_driver ? kGpuDriverBytes : 0.0);
    limit.rlim_cur = limit.rlim_max = std::min<rlim_t>(rlim_t(std::min(data, 0x1p62)), limit.rlim_max);
    std::vector<char*> argv = {const_cast<char*>(path.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    // The parent-death signal comes when the thread that forked ends: asked only from the
    // process's main thread, which ends with the process (a worker started on another thread
    // still ends at its client's hang-up, worker_main.cpp).
    const pid_t parent = ::getpid();
    const bool main_thread = ::gettid() == parent;
    pid = ::fork();
    if (pid == 0) {
      // The child: only async-signal-safe calls until exec; exec's errno goes back through the pipe.
      if (main_thread) ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(127);  // the client died before the signal was set
      ::dup2(fds[1], STDIN_FILENO);
      ::dup2(fds[1], STDOUT_FILENO);
      int error = kAddressSanitizer || ::setrlimit(RLIMIT_DATA, &limit) == 0 ? 0 : errno;
      if (error == 0) ::execve(path.c_str(), argv.data(), environ);
      error = error ? error : errno;
      [[maybe_unused]] const ssize_t reported = ::write(exec_report[1], &error, sizeof error);
      ::_exit(127);
    }
    const int fork_error = pid < 0 ? errno : 0;
    ::close(fds[1]);
    ::close(exec_report[1]);
    fd = fds[0];
    int exec_error = fork_error;
    // Reads the child's report: nothing (EOF) once exec succeeded; EINTR repeats.
    while (pid > 0 && ::read(exec_report[0], &exec_error, sizeof exec_error) < 0 && errno == EINTR) {
    }
    ::close(exec_report[0]);
    if (exec_error != 0) {
      if (pid > 0) ::waitpid(pid, nullptr, 0);
      pid = -1;
      close_channel();
      failure = std::string("cannot start: ") + std::strerror(exec_error);
      throw std::runtime_error(name + ": " + failure +
                               " (build the heightmarch-glsl-worker target, or set HEIGHTMARCH_GLSL_WORKER)");
    }
  }

  // Checks the protocol version an answer began with.
  void check_version(std::uint32_t version) {
    if (version != protocol::kVersion)
      fail("speaks protocol " + std::to_string(version) + ", this build " +
               std::to_string(protocol::kVersion) + " (a stale build?); killed",
           true);
  }

  // Starts the worker's draw loop and reads its greeting within kStartupTimeout.
  void start() {
    sent_map.reset();
    sent_rays.reset();
    prepared = false;
    spawn(arguments(), *target.path == GlPath::egl && target.device != "software");
    std::uint32_t protocol_version = 0;
    call(std::nullopt, {}, Message::ready, "start-up", kStartupTimeout, [&](protocol::Reader& reader) {
      reader.value(protocol_version);
      if (protocol_version == protocol::kVersion)
        protocol::read(reader, renderer);
      else
        reader.text(renderer.renderer);  // what a stale worker sends: not read as this build's
    });
    check_version(protocol_version);
  }

  // Starts the worker to answer one question (--paths; --list-devices, which makes a context on
  // each device, a GPU's among them) and reads its answer within `timeout`; the worker exits
  // after it.
  void ask(const std::vector<std::string>& args, bool gpu_driver, Message answer, const char* what,
           Seconds timeout, const std::function<void(protocol::Reader&)>& parse) {
    spawn(args, gpu_driver);
    std::uint32_t protocol_version = 0;
    call(std::nullopt, {}, answer, what, timeout, [&](protocol::Reader& reader) {
      reader.value(protocol_version);
      if (protocol_version != protocol::kVersion)
        throw protocol::BadMessage("protocol " + std::to_string(protocol_version));
      parse(reader);
    });
    end("asked", false);
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
    out_of_memory = done > 0 && WIFEXITED(status) && WEXITSTATUS(status) == protocol::kOutOfMemoryStatus;
    return done < 0 ? std::string("was lost (") + std::strerror(errno) + ")" : describe_status(status);
  }

  void close_channel() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }

  // Sends the request (none: only reads an answer) within `send_timeout`, then waits `timeout`
  // at most for an answer, which must be of type `answer`, and hands it to `parse`. The worker's
  // errors come back as they were thrown there (its other errors named after it); losing the
  // worker or a garbled answer is a runtime_error, or an InputError naming the brought-in shader
  // `shader` when that is what the worker was compiling or drawing; a compile or a draw past its
  // bound is compile_timeout() or draw_timeout(), any other step past its bound a runtime_error
  // naming it. A worker that is gone is started again (revive()) before anything else is asked
  // of it.
  void call(std::optional<Message> request, const protocol::Writer& payload, Message answer, const char* what,
            Seconds timeout, const std::function<void(protocol::Reader&)>& parse,
            const std::string& shader = "", Seconds send_timeout = Seconds(kStepFloorSeconds)) {
    if (!failure.empty()) {
      const std::string why = failure;
      start();
      throw std::runtime_error(name + " was restarted (before: " + why + "); prepare before a " + what);
    }
    Message type = Message::error;
    std::string text;
    const auto after = [](Seconds wait) {
      return std::chrono::steady_clock::now() +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(wait);
    };
    try {
      if (request) {
        try {
          protocol::send(fd, *request, payload, after(send_timeout));
        } catch (const protocol::ChannelTimeout&) {
          fail("did not take the " + std::string(what) + " request within " +
                   seconds_text(send_timeout.count()) + " s; killed",
               true);
        }
      }
      std::vector<char> reply;
      type = protocol::receive(fd, reply, after(timeout), memory_budget_left());
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
      if (answer == Message::drawn) draw_timeout();
      if (answer == Message::compiled) compile_timeout(shader);
      fail("no answer to " + std::string(what) + " within " + seconds_text(timeout.count()) + " s; killed",
           true);
    } catch (const protocol::ChannelClosed& e) {
      lost(std::string(e.what()) + " during " + what, shader, what);
    } catch (const protocol::BadMessage& e) {
      end(std::string(e.what()) + " during " + what + "; killed", true);
      throw std::runtime_error(name + ": " + failure);
    }
    if (type == Message::input_error) throw InputError(text);
    if (type == Message::error) throw std::runtime_error(name + ": " + text);
    const std::string received = std::to_string(unsigned(type));
    fail("answered " + std::string(what) + " with message type " + received + "; killed", true);
  }

  // The worker closed the channel: it exited or died. Reaped; while it compiled or drew a
  // brought-in shader, the shader's fault, named (a worker killed there has most likely run into
  // its memory limit), else a runtime_error.
  [[noreturn]] void lost(const std::string& why, const std::string& shader, const char* doing) {
    end(why, false);
    const std::string budget = bytes_text(double(memory_limit)) + " (" + memory_budget_source() + ")";
    const std::string after = "; it restarts for the next request";
    if (out_of_memory)
      throw InputError((shader.empty() ? "" : shader + ": ") +
                       "the GLSL worker ran out of memory within its budget of " + budget + " during its " +
                       doing + after);
    if (shader.empty()) throw std::runtime_error(name + ": " + failure);
    throw InputError(shader + ": the GLSL worker " + how_it_ended + " during its " + doing +
                     " (a crash, or its memory limit of " + budget + " reached)" + after);
  }

  // A compile past kCompileTimeout: the brought-in shader's fault (an InputError), or a
  // runtime_error for a built-in technique.
  [[noreturn]] void compile_timeout(const std::string& shader) {
    const std::string bound = "its bound of " + seconds_text(kCompileTimeout.count()) + " s";
    const std::string what = "compiling it ran past " + bound;
    end("a compile ran past " + bound + "; killed", true);
    const std::string after = "; the GLSL worker was killed and restarts for the next request";
    if (!shader.empty())
      throw InputError(shader + ": " + what + " (does the preprocessor or the compiler run away?)" + after);
    throw std::runtime_error(name + ": the built-in program's " + what + after);
  }

  static std::string seconds_text(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", seconds);
    return text;
  }

  // A worker that is gone is started again, knowing nothing: a prepare sends it everything.
  void revive() {
    if (!failure.empty()) start();
  }

  // Ends the worker (killed, or reaped after it closed the channel) and keeps why; the next call
  // starts a new one.
  void end(const std::string& why, bool kill) {
    if (kill && pid > 0) ::kill(pid, SIGKILL);
    close_channel();
    how_it_ended = reap();
    failure = kill ? why : why + "; the worker " + how_it_ended;
  }

  [[noreturn]] void fail(const std::string& why, bool kill) {
    end(why, kill);
    throw std::runtime_error(name + ": " + failure);
  }

  // The watchdog: a draw past its bound is a brought-in shader's fault (an InputError), or a
  // runtime_error for a built-in technique.
  [[noreturn]] void draw_timeout() {
    const std::string what = "the GLSL draw of " + std::to_string(rays) + " rays ran past its bound of " +
                             seconds_text(draw_bound) + " s";
    end(what + "; killed", true);
    const std::string after = "; the GLSL worker was killed and restarts for the next request";
    if (!shader_path.empty()) throw InputError(shader_path + ": " + what + " (an endless loop?)" + after);
    throw std::runtime_error(name + ": " + what + after);
  }

  ~WorkerProcess() {
    close_channel();  // EOF on its stdin: the worker destroys its context and exits
    reap();
  }
};

// A worker to be started only to answer one question, named for its errors.
void ask_only(WorkerProcess& w, const char* what) {
  w.path = worker_path();
  w.name = "GLSL worker " + w.path + " (" + what + ")";
}

}  // namespace

struct GlslRunner::Worker : WorkerProcess {};

std::vector<GlPath> gl_paths_built() {
  static std::mutex mutex;
  static std::optional<std::vector<GlPath>> built;  // the worker is the same for the whole process
  const std::lock_guard lock(mutex);
  if (built) return *built;
  WorkerProcess w;
  ask_only(w, "asked which GL paths it has");
  std::vector<GlPath> paths;
  w.ask({"--paths"}, false, Message::paths, "--paths", kStartupTimeout, [&](protocol::Reader& reader) {
    std::vector<std::uint32_t> ids;
    reader.array(ids);
    for (std::uint32_t id : ids) {
      bool known = false;
#define HEIGHTMARCH_GL_PATH_KNOWN(path_id, ...) \
  if (id == std::uint32_t(GlPath::path_id)) known = true, paths.push_back(GlPath::path_id);
      HEIGHTMARCH_GL_PATHS(HEIGHTMARCH_GL_PATH_KNOWN)
#undef HEIGHTMARCH_GL_PATH_KNOWN
      if (!known) throw protocol::BadMessage("GL path " + std::to_string(id) + " is none of the list's");
    }
    if (paths.empty()) throw protocol::BadMessage("no GL path");
  });
  built = paths;
  return paths;
}

GlTarget resolved(const GlTarget& target) {
  check(target);
  GlTarget r = target;
  const std::vector<GlPath> built = gl_paths_built();
  if (!r.path) r.path = r.device.empty() ? built.front() : GlPath::egl;
  if (std::find(built.begin(), built.end(), *r.path) == built.end())
    throw InputError("--gl " + to_string(*r.path) + ": this heightmarch's GLSL worker was built without " +
                     display_name(*r.path) + " (its library was not found when it was built); it has " +
                     display_name(built.front()));
  return r;
}

std::vector<GlDevice> list_gl_devices() {
  WorkerProcess w;
  ask_only(w, "asked for EGL's devices");
  std::vector<GlDevice> devices;
  // Each device gets a context, as at a start-up.
  w.ask({"--list-devices", "--memory-limit", std::to_string(memory_budget())}, true, Message::devices,
        "--list-devices", Seconds(kStartupTimeout.count() * 4),
        [&](protocol::Reader& reader) { protocol::read(reader, devices); });
  return devices;
}

GlslRunner& GlslRunner::instance(int threads, const GlTarget& target) {
  const int wanted = threads > 0 ? threads : tbb::info::default_concurrency();
  const GlTarget gl = resolved(target);
  static std::mutex mutex;
  // Workers stop when these are destroyed at exit.
  static std::map<std::tuple<GlPath, std::string, int>, std::unique_ptr<GlslRunner>> runners;
  const std::lock_guard lock(mutex);
  std::unique_ptr<GlslRunner>& runner = runners[{*gl.path, gl.device, wanted}];
  if (!runner) runner.reset(new GlslRunner(wanted, gl));
  return *runner;
}

GlslRunner::GlslRunner(int threads, const GlTarget& target)
    : worker_(std::make_unique<Worker>()), threads_(threads) {
  Worker& w = *worker_;
  w.path = worker_path();
  w.threads = threads;
  w.target = target;
  // The path is named where it is not the worker's first (OSMesa where built).
  const std::string gl =
      *target.path == gl_paths_built().front() && target.device.empty()
          ? ""
          : display_name(*target.path) + (target.device.empty() ? "" : " " + target.device) + ", ";
  w.name = "GLSL worker " + w.path + " (" + gl + std::to_string(threads) +
           (threads == 1 ? " thread)" : " threads)");
  w.start();
  renderer_ = w.renderer;
}

GlslRunner::~GlslRunner() = default;

void GlslRunner::prepare(const DepthMap& map, const TechniqueParams& params, const RayBatch& rays,
                         const std::string& shader_path) {
  Worker& w = *worker_;
  w.revive();
  const bool send_map = !w.holds(map), send_rays = !w.holds(rays);
  protocol::Writer request;
  protocol::write(request, params);
  request.value(std::uint8_t(send_map));
  if (send_map) protocol::write(request, map);
  request.value(std::uint8_t(send_rays));
  std::optional<ScreenLayout> layout;
  if (send_rays) {
    layout = screen_layout(rays);
    protocol::write(request, layout->drawn);
  }
  request.text(shader_path);
  w.prepared = false;
  const Seconds upload(upload_bound_seconds(params, request.bytes().size(), map.texels.size(), shader_path));
  try {
    // The request sent and the program compiled, each under its own bound; then the uploads and
    // precomputed textures under theirs.
    w.call(
        Message::prepare, request, Message::compiled, "compile", kCompileTimeout, [](protocol::Reader&) {},
        shader_path, upload);
    w.call(std::nullopt, {}, Message::done, "upload", upload, [](protocol::Reader&) {});
  } catch (...) {
    // A prepare that failed may have replaced either or neither: the next one sends both.
    w.sent_map.reset();
    w.sent_rays.reset();
    throw;
  }
  if (send_map) w.sent_map = map;
  if (send_rays) {
    w.sent_rays.emplace();
    const auto arrays = protocol::ray_arrays(rays);
    for (std::size_t i = 0; i < arrays.size(); ++i) (*w.sent_rays)[i] = *arrays[i];
    w.sent_origin = rays.origin;
    w.sent_grid = Worker::grid(rays);
    w.texel_of = std::move(layout->texel_of);
    w.rays = layout->drawn.rays.size();
  }
  w.prepared = true;
  w.shader_path = shader_path;
  w.draw_bound = draw_bound_seconds(params, w.rays);
}

GlDrawTime GlslRunner::draw() {
  Worker& w = *worker_;
  GlDrawTime time;
  w.call(
      Message::draw, {}, Message::drawn, "draw", Seconds(w.draw_bound),
      [&](protocol::Reader& reader) {
        std::uint8_t timed = 0;
        double timer = 0;
        reader.value(time.wall_seconds);
        reader.value(timed);
        reader.value(timer);
        if (timed) time.timer_seconds = timer;
      },
      w.shader_path);
  return time;
}

void GlslRunner::read(HitBuffers& hits, bool& samples_known) const {
  std::uint8_t known = 0;
  const Seconds bound(kStepFloorSeconds + double(worker_->rays) * kReadSecondsPerRay);
  HitBuffers drawn;
  worker_->call(Message::read, {}, Message::hits, "read-back", bound, [&](protocol::Reader& reader) {
    protocol::read(reader, drawn, worker_->rays);
    reader.value(known);
  });
  samples_known = known != 0;
  // Each ray's hit from its texel.
  const std::vector<std::uint32_t>& texel_of = worker_->texel_of;
  hits.resize(texel_of.size());
  hits.for_each([&](HitChannel channel, auto& to) {
    drawn.for_each([&](HitChannel from_channel, const auto& from) {
      if constexpr (std::is_same_v<std::decay_t<decltype(to)>, std::decay_t<decltype(from)>>)
        if (from_channel == channel)
          for (std::size_t i = 0; i < texel_of.size(); ++i) to[i] = from[texel_of[i]];
    });
  });
}

}  // namespace heightmarch
