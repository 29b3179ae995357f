// heightmarch-glsl-worker --threads N --memory-limit BYTES [--gl PATH] [--gl-device DEVICE]: one GL
// context (gl_context.hpp: OSMesa or EGL, and through EGL one of its devices; without --gl, OSMesa
// where it was built with it, else EGL) with llvmpipe at N threads, driven by GlslRunner
// (src/glsl/glsl_runner.cpp) over stdin/stdout with the messages of src/glsl/protocol.hpp. It
// exits when its stdin closes, and when its client dies (the client starts it with a parent-death
// signal; a thread here also watches the channel for the client's hang-up). BYTES is the run's
// memory budget, which its own checks ask as heightmarch's do; its client starts it under an OS
// limit (RLIMIT_DATA) of BYTES, which it lowers once its context exists to what the budget leaves
// beyond it.
// heightmarch-glsl-worker --paths, and --list-devices --memory-limit BYTES, answer one message (the
// GL paths it was built with; EGL's devices) and exit.
//
// For the tests only: HEIGHTMARCH_GLSL_WORKER_STALL=start-up|upload|read-back stops the worker
// (SIGSTOP) at that step, as a worker that hangs there, which its client must notice.
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "glsl/gl_runner.hpp"
#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "util/sanitizers.hpp"

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;

// Stops the worker at `step` when the tests ask for it (HEIGHTMARCH_GLSL_WORKER_STALL).
void stall_if_asked(const char* step) {
  const char* stall = std::getenv("HEIGHTMARCH_GLSL_WORKER_STALL");
  if (stall && std::string(stall) == step) ::raise(SIGSTOP);
}

// Answers one request, read and checked whole first (read_request); InputErrors and other errors
// are the caller's to send.
void serve(GlRunner& runner, Message type, const std::vector<char>& payload, int out) {
  const protocol::Request request = protocol::read_request(type, payload);
  protocol::Writer answer;
  if (const auto* prepare = std::get_if<protocol::PrepareRequest>(&request)) {
    // The program first, under the client's compile deadline; then the uploads, under theirs.
    runner.compile(prepare->params, prepare->shader_path);
    protocol::send(out, Message::compiled, answer, std::nullopt);
    stall_if_asked("upload");
    if (prepare->map) runner.set_depth_map(*prepare->map);
    if (prepare->rays) runner.set_rays(*prepare->rays);
    runner.prepare(prepare->params);
    return protocol::send(out, Message::done, answer, std::nullopt);
  }
  if (std::holds_alternative<protocol::DrawRequest>(request)) {
    runner.clear_hits();
    const DrawTimes times = runner.draw();
    answer.value(times.wall_seconds);
    answer.value(std::uint8_t(times.timer_seconds.has_value()));
    answer.value(times.timer_seconds.value_or(0.0));
    return protocol::send(out, Message::drawn, answer, std::nullopt);
  }
  stall_if_asked("read-back");
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  protocol::write(answer, hits);
  answer.value(std::uint8_t(samples_known));
  protocol::send(out, Message::hits, answer, std::nullopt);
}

// The client's end of the channel, watched on a thread of its own: when the client is gone (it
// exited or was killed, even while a draw runs here) the worker ends at once. Only a socket says
// so: a worker run by hand on a file or a pipe is left to read to its end.
void exit_when_the_client_hangs_up(int in) {
  struct stat st {};
  if (::fstat(in, &st) != 0 || !S_ISSOCK(st.st_mode)) return;
  std::thread([in] {
    pollfd p{in, POLLRDHUP, 0};
    // Each pass sleeps in poll until the hang-up; EINTR repeats it.
    while (::poll(&p, 1, -1) < 0 && errno == EINTR) {
    }
    ::_exit(0);
  }).detach();
}

// The OS limit on what the worker may allocate (RLIMIT_DATA), lowered to what it has allocated now
// plus what the budget leaves beside what it holds: a compile or a draw that runs away (a shader
// of nested #defines, a huge array) fails an allocation instead of growing past the budget.
void limit_data_to_budget() {
  const ProcessMemory now = process_memory();
  rlimit limit{};
  if (kAddressSanitizer || now.data == 0 || ::getrlimit(RLIMIT_DATA, &limit) != 0) return;
  const rlim_t bytes = rlim_t(now.data + memory_budget_left());
  limit.rlim_cur = std::min(limit.rlim_cur, bytes);
  limit.rlim_max = std::min(limit.rlim_max, bytes);
  ::setrlimit(RLIMIT_DATA, &limit);
}

void send_error(int out, Message type, const std::string& text) {
  protocol::Writer answer;
  answer.text(text);
  protocol::send(out, type, answer, std::nullopt);
}

// The worker's questions answered without a draw loop: --paths and --list-devices.
int answer(Message type, const protocol::Writer& payload) {
  protocol::send(STDOUT_FILENO, type, payload, std::nullopt);
  return 0;
}

int run(const GlTarget& target, int threads) {
  // The protocol gets its own copy of stdout; fd 1 becomes stderr, so a library's stray printf
  // goes to the terminal instead of into a message.
  const int in = STDIN_FILENO;
  const int out = ::dup(STDOUT_FILENO);
  if (out < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    std::perror("heightmarch-glsl-worker: dup");
    return 1;
  }
  ::signal(SIGPIPE, SIG_IGN);  // a vanished client is a write error, handled as EOF below
  exit_when_the_client_hangs_up(in);
  try {
    std::unique_ptr<GlRunner> runner;
    try {
      stall_if_asked("start-up");
      runner = std::make_unique<GlRunner>(make_gl_context(target, threads));
      // Its code and libraries (OSMesa or EGL's driver, LLVM) and its context are resident now.
      check_memory_budget_covers_footprint("the GLSL worker");
      limit_data_to_budget();
    } catch (const InputError& e) {
      send_error(out, Message::input_error, e.what());
      return 1;
    } catch (const std::exception& e) {
      send_error(out, Message::error, e.what());
      return 1;
    }
    protocol::Writer ready;
    ready.value(protocol::kVersion);
    protocol::write(ready, runner->renderer());
    protocol::send(out, Message::ready, ready, std::nullopt);
    std::vector<char> payload;
    // One request per pass, until the client closes stdin (receive throws ChannelClosed) or sends
    // bytes that are no message (BadMessage: the channel is lost, said on stderr).
    for (;;) {
      const Message type = protocol::receive(in, payload, std::nullopt, memory_budget_left());
      try {
        serve(*runner, type, payload, out);
      } catch (const InputError& e) {
        send_error(out, Message::input_error, e.what());
      } catch (const protocol::BadMessage& e) {
        send_error(out, Message::error, std::string("a malformed request: ") + e.what());
      } catch (const protocol::ChannelClosed&) {
        throw;
      } catch (const std::bad_alloc&) {
        send_error(out, Message::input_error,
                   "the GLSL worker ran out of memory within its budget of " +
                       bytes_text(double(memory_budget())) + " (" + memory_budget_source() + ")");
      } catch (const std::exception& e) {
        send_error(out, Message::error, e.what());
      }
    }
  } catch (const protocol::ChannelClosed&) {
    return 0;  // the client is gone or done
  } catch (const protocol::BadMessage& e) {
    std::fprintf(stderr,
                 "heightmarch-glsl-worker: a malformed message from its client: %s; the channel is lost\n",
                 e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "heightmarch-glsl-worker: out of memory within its budget of %s\n",
                 bytes_text(double(memory_budget())).c_str());
    return protocol::kOutOfMemoryStatus;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", error_line(e.what()).c_str());
    return 1;
  }
}

}  // namespace
}  // namespace heightmarch

int main(int argc, char** argv) {
  using namespace heightmarch;
  const std::string usage = "usage: heightmarch-glsl-worker --threads N --memory-limit BYTES [--gl " +
                            gl_path_names() +
                            "] [--gl-device DEVICE], --paths, or --list-devices --memory-limit BYTES "
                            "(started by heightmarch, not by hand)\n";
  if (argc == 2 && std::string(argv[1]) == "--paths") {
    protocol::Writer paths;
    paths.value(protocol::kVersion);
    std::vector<std::uint32_t> built;
    for (GlPath p : built_gl_paths()) built.push_back(std::uint32_t(p));
    paths.array(built);
    return answer(Message::paths, paths);
  }
  // The options as NAME VALUE pairs, each at most once.
  std::map<std::string, std::string> options;
  const bool list = argc >= 2 && std::string(argv[1]) == "--list-devices";
  for (int i = list ? 2 : 1; i < argc; i += 2) {
    const std::string name = argv[i];
    const bool known = name == "--memory-limit" ||
                       (!list && (name == "--threads" || name == "--gl" || name == "--gl-device"));
    if (!known || i + 1 >= argc || !options.emplace(name, argv[i + 1]).second) {
      std::fputs(usage.c_str(), stderr);
      return 2;
    }
  }
  if (!options.count("--memory-limit") || (!list && !options.count("--threads"))) {
    std::fputs(usage.c_str(), stderr);
    return 2;
  }
  GlTarget target;
  long threads = 1;
  try {
    set_memory_budget(parse_memory_limit(options["--memory-limit"], "--memory-limit"),
                      "the GLSL worker's, heightmarch's own");
    if (list) {
      protocol::Writer devices;
      devices.value(protocol::kVersion);
      protocol::write(devices, list_gl_devices(GlPath::egl));
      return answer(Message::devices, devices);
    }
    char* end = nullptr;
    threads = std::strtol(options["--threads"].c_str(), &end, 10);
    if (*end != '\0' || threads < 1 || threads > 1024)
      throw InputError("--threads " + printable(options["--threads"]) + ": not a count from 1 to 1024");
    target = parse_gl_target(options["--gl"], options["--gl-device"]);
  } catch (const InputError& e) {
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", error_line(e.what()).c_str());
    return 1;
  }
  return run(target, int(threads));
}
