// libFuzzer: any bytes as the stream a GLSL worker reads from its client, through the worker's own
// message reader (receive, then read_request; src/glsl/protocol.hpp). Each message ends the stream
// (ChannelClosed, BadMessage: the worker says so and exits), is refused with an answer (a
// BadMessage or InputError from read_request: the worker stays usable) or is a request every
// field of which passed the command line's checks; never a crash, undefined behaviour (UBSan) or
// an allocation sized by a header's claim rather than by the bytes that came (the reader is given
// a budget of 2^40 bytes; libFuzzer's malloc limit catches a zero-fill of a claimed 4 GiB).
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <variant>
#include <vector>

#include "glsl/protocol.hpp"
#include "heightmarch/error.hpp"

using namespace heightmarch;
namespace protocol = heightmarch::glsl_protocol;

namespace {

// What read_request promises of a prepare it returns.
void check_prepare(const protocol::PrepareRequest& p) {
  try {
    check(p.params);
    if (p.map) check_depth_map(*p.map, "fuzz");
    if (p.rays) check_rays(p.rays->rays);
  } catch (const InputError&) {
    __builtin_trap();
  }
  if (p.shader_path.find('\0') != std::string::npos) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const int fd = ::memfd_create("worker-messages", MFD_CLOEXEC);
  if (fd < 0 || ::ftruncate(fd, 0) != 0 || ::pwrite(fd, data, size, 0) != ssize_t(size) ||
      ::lseek(fd, 0, SEEK_SET) != 0)
    return 0;
  std::vector<char> payload;
  // One message per pass: each takes a header's 16 bytes at least, or ends the stream.
  for (;;) {
    protocol::Message type{};
    try {
      type = protocol::receive(fd, payload, std::nullopt, std::uint64_t(1) << 40);
    } catch (const protocol::ChannelClosed&) {
      break;
    } catch (const protocol::BadMessage&) {
      break;
    }
    if (payload.size() > size) __builtin_trap();
    try {
      const protocol::Request request = protocol::read_request(type, payload);
      if (const auto* prepare = std::get_if<protocol::PrepareRequest>(&request)) check_prepare(*prepare);
    } catch (const protocol::BadMessage&) {
    } catch (const InputError&) {
    }
  }
  return 0;
}
