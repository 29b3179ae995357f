// heightmarch-glsl-worker --threads N: one OSMesa (llvmpipe) GL context at N threads, driven by
// GlslRunner (src/glsl/glsl_client.cpp) over stdin/stdout with the messages of
// src/glsl/protocol.hpp. It exits when its stdin closes.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "glsl/osmesa_runner.hpp"
#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

namespace protocol = glsl_protocol;
using protocol::Message;

// Answers one request; InputErrors and other errors are the caller's to send.
void serve(OsmesaRunner& runner, Message type, const std::vector<char>& payload, int out) {
  protocol::Reader reader(payload);
  protocol::Writer answer;
  switch (type) {
    case Message::prepare: {
      TechniqueParams params;
      DepthMap map;
      RayBatch rays;
      std::uint8_t map_sent = 0, rays_sent = 0;
      std::string shader_path;
      protocol::read(reader, params);
      reader.value(map_sent);
      if (map_sent) protocol::read(reader, map);
      reader.value(rays_sent);
      if (rays_sent) protocol::read(reader, rays);
      reader.text(shader_path);
      reader.finish();
      if (map_sent) runner.set_depth_map(map);
      if (rays_sent) runner.set_rays(rays);
      runner.prepare(params, shader_path);
      return protocol::send(out, Message::done, answer, std::nullopt);
    }
    case Message::draw: {
      reader.finish();
      runner.clear_hits();
      const auto start = std::chrono::steady_clock::now();
      runner.draw();
      answer.value(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      return protocol::send(out, Message::drawn, answer, std::nullopt);
    }
    case Message::read: {
      reader.finish();
      HitBuffers hits;
      bool samples_known = false;
      runner.read(hits, samples_known);
      protocol::write(answer, hits);
      answer.value(std::uint8_t(samples_known));
      return protocol::send(out, Message::hits, answer, std::nullopt);
    }
    default:
      throw std::runtime_error("unknown request type " + std::to_string(unsigned(type)));
  }
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
    // One request per pass, until the client closes stdin (receive throws ChannelClosed).
    for (;;) {
      const Message type = protocol::receive(in, payload, std::nullopt);
      try {
        serve(*runner, type, payload, out);
      } catch (const InputError& e) {
        send_error(out, Message::input_error, e.what());
      } catch (const protocol::ChannelClosed&) {
        throw;
      } catch (const std::exception& e) {
        send_error(out, Message::error, e.what());
      }
    }
  } catch (const protocol::ChannelClosed&) {
    return 0;  // the client is gone or done
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heightmarch-glsl-worker: %s\n", e.what());
    return 1;
  }
}

}  // namespace
}  // namespace heightmarch

int main(int argc, char** argv) {
  const std::string usage =
      "usage: heightmarch-glsl-worker --threads N (started by heightmarch, not by hand)\n";
  if (argc != 3 || std::string(argv[1]) != "--threads") {
    std::fputs(usage.c_str(), stderr);
    return 2;
  }
  char* end = nullptr;
  const long threads = std::strtol(argv[2], &end, 10);
  if (*end != '\0' || threads < 1 || threads > 1024) {
    std::fprintf(stderr, "heightmarch-glsl-worker: --threads %s: not a count from 1 to 1024\n", argv[2]);
    return 2;
  }
  return heightmarch::run(int(threads));
}
