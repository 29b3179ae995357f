// heightmarch-glsl-worker --threads N --memory-limit BYTES: one OSMesa (llvmpipe) GL context at N
// threads, driven by GlslRunner (src/glsl/glsl_runner.cpp) over stdin/stdout with the messages of
// src/glsl/protocol.hpp. It exits when its stdin closes. BYTES is the run's memory budget, which
// its own checks ask as heightmarch's do; its client starts it under an OS limit (RLIMIT_DATA) of
// BYTES, which it lowers once its context exists to what the budget leaves beyond it.
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <variant>
#include <vector>

#include "glsl/osmesa_runner.hpp"
#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"
#include "util/sanitizers.hpp"

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;

// Answers one request, read and checked whole first (read_request); InputErrors and other errors
// are the caller's to send.
void serve(OsmesaRunner& runner, Message type, const std::vector<char>& payload, int out) {
  const protocol::Request request = protocol::read_request(type, payload);
  protocol::Writer answer;
  if (const auto* prepare = std::get_if<protocol::PrepareRequest>(&request)) {
    // The program first, under the client's compile deadline; then the uploads.
    runner.compile(prepare->params, prepare->shader_path);
    protocol::send(out, Message::compiled, answer, std::nullopt);
    if (prepare->map) runner.set_depth_map(*prepare->map);
    if (prepare->rays) runner.set_rays(*prepare->rays);
    runner.prepare(prepare->params);
    return protocol::send(out, Message::done, answer, std::nullopt);
  }
  if (std::holds_alternative<protocol::DrawRequest>(request)) {
    runner.clear_hits();
    const auto start = std::chrono::steady_clock::now();
    runner.draw();
    answer.value(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return protocol::send(out, Message::drawn, answer, std::nullopt);
  }
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  protocol::write(answer, hits);
  answer.value(std::uint8_t(samples_known));
  protocol::send(out, Message::hits, answer, std::nullopt);
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

int run(int threads) {
  // The protocol gets its own copy of stdout; fd 1 becomes stderr, so a library's stray printf
  // goes to the terminal instead of into a message.
  const int in = STDIN_FILENO;
  const int out = ::dup(STDOUT_FILENO);
  if (out < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    std::perror("heightmarch-glsl-worker: dup");
    return 1;
  }
  ::signal(SIGPIPE, SIG_IGN);  // a vanished client is a write error, handled as EOF below
  try {
    std::unique_ptr<OsmesaRunner> runner;
    try {
      runner = std::make_unique<OsmesaRunner>(threads);
      // Its code and libraries (OSMesa, LLVM) and its context are resident now.
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
    ready.text(runner->renderer());
    ready.text(runner->version());
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
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", printable(e.what()).c_str());
    return 1;
  }
}

}  // namespace
}  // namespace heightmarch

int main(int argc, char** argv) {
  const std::string usage =
      "usage: heightmarch-glsl-worker --threads N --memory-limit BYTES (started by heightmarch, not by "
      "hand)\n";
  if (argc != 5 || std::string(argv[1]) != "--threads" || std::string(argv[3]) != "--memory-limit") {
    std::fputs(usage.c_str(), stderr);
    return 2;
  }
  char* end = nullptr;
  const long threads = std::strtol(argv[2], &end, 10);
  if (*end != '\0' || threads < 1 || threads > 1024) {
    std::fprintf(stderr, "heightmarch-glsl-worker: --threads %s: not a count from 1 to 1024\n",
                 heightmarch::printable(argv[2]).c_str());
    return 2;
  }
  try {
    heightmarch::set_memory_budget(heightmarch::parse_memory_limit(argv[4], "--memory-limit"),
                                   "the GLSL worker's, heightmarch's own");
  } catch (const heightmarch::InputError& e) {
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", e.what());
    return 2;
  }
  return heightmarch::run(int(threads));
}
