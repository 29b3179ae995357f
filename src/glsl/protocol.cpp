#include "glsl/protocol.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

namespace heightmarch::glsl_protocol {

namespace {

// The fields of TechniqueParams in wire order, once for both directions (Writer::value takes
// const&, Reader::value &).
template <class Io, class Params>
void params_fields(Io& io, Params& params) {
  io.value(params.technique);
  io.value(params.layers.min_layers);
  io.value(params.layers.max_layers);
  io.value(params.scale);
  io.value(params.wrap);
  io.value(params.discard);
  io.value(params.light);
}

}  // namespace

// The refine count travels resolved (the registry's default where none was given).
void write(Writer& w, const TechniqueParams& params) {
  params_fields(w, params);
  w.value(params.refine_steps());
}

void read(Reader& r, TechniqueParams& params) {
  params_fields(r, params);
  int refine = 0;
  r.value(refine);
  params.refine = refine;
}

void write(Writer& w, const DepthMap& map) {
  w.value(map.width);
  w.value(map.height);
  w.array(map.texels);
}

void read(Reader& r, DepthMap& map) {
  r.value(map.width);
  r.value(map.height);
  r.array(map.texels);
  if (map.width < 0 || map.height < 0 ||
      map.texels.size() != std::size_t(map.width) * std::size_t(map.height))
    throw ChannelClosed("depth map size does not match its texels");
}

void write(Writer& w, const RayBatch& rays) {
  for (const auto* a : {&rays.tx, &rays.ty, &rays.vx, &rays.vy, &rays.vz}) w.array(*a);
}

void read(Reader& r, RayBatch& rays) {
  for (auto* a : {&rays.tx, &rays.ty, &rays.vx, &rays.vy, &rays.vz}) r.array(*a);
  for (const auto* a : {&rays.ty, &rays.vx, &rays.vy, &rays.vz})
    if (a->size() != rays.tx.size()) throw ChannelClosed("ray arrays of different lengths");
}

void write(Writer& w, const HitBuffers& hits) {
  for (const auto* a : {&hits.u, &hits.v, &hits.depth, &hits.shadow}) w.array(*a);
  w.array(hits.samples);
  w.array(hits.discarded);
}

void read(Reader& r, HitBuffers& hits) {
  for (auto* a : {&hits.u, &hits.v, &hits.depth, &hits.shadow}) r.array(*a);
  r.array(hits.samples);
  r.array(hits.discarded);
  const std::size_t n = hits.u.size();
  if (hits.v.size() != n || hits.depth.size() != n || hits.shadow.size() != n || hits.samples.size() != n ||
      hits.discarded.size() != n)
    throw ChannelClosed("hit arrays of different lengths");
}

namespace {

constexpr std::uint64_t kMaxPayload = std::uint64_t(1) << 36;  // a corrupt header cannot ask for more

// Waits until fd is ready for `events`; false once the deadline has passed.
bool wait_for(int fd, short events, Deadline deadline) {
  // Each pass either returns or sleeps in poll until the deadline; EINTR repeats it.
  for (;;) {
    int timeout_ms = -1;
    if (deadline) {
      const auto left =
          std::chrono::ceil<std::chrono::milliseconds>(*deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      timeout_ms = int(std::min<long long>(left.count(), 1 << 30));
    }
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, timeout_ms);
    if (n > 0) return true;
    if (n < 0 && errno != EINTR) throw std::system_error(errno, std::generic_category(), "poll");
  }
}

void write_all(int fd, const char* data, std::size_t n, Deadline deadline) {
  // Every pass writes at least one byte or throws.
  while (n > 0) {
    if (!wait_for(fd, POLLOUT, deadline)) throw ChannelTimeout("timed out writing");
    // MSG_NOSIGNAL: a dead peer is an error here, not a SIGPIPE; a pipe (a worker run by hand) takes write().
    ssize_t done = ::send(fd, data, n, MSG_NOSIGNAL);
    if (done < 0 && errno == ENOTSOCK) done = ::write(fd, data, n);
    if (done < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (done < 0 && errno == EPIPE) throw ChannelClosed("channel closed");
    if (done < 0) throw std::system_error(errno, std::generic_category(), "write");
    data += done;
    n -= std::size_t(done);
  }
}

void read_all(int fd, char* data, std::size_t n, Deadline deadline) {
  // Every pass reads at least one byte or throws.
  while (n > 0) {
    if (!wait_for(fd, POLLIN, deadline)) throw ChannelTimeout("timed out reading");
    const ssize_t done = ::read(fd, data, n);
    if (done < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (done < 0 && errno == ECONNRESET) throw ChannelClosed("channel closed");
    if (done < 0) throw std::system_error(errno, std::generic_category(), "read");
    if (done == 0) throw ChannelClosed("channel closed");
    data += done;
    n -= std::size_t(done);
  }
}

}  // namespace

void send(int fd, Message type, const Writer& payload, Deadline deadline) {
  Header header;
  header.type = type;
  header.size = payload.bytes().size();
  write_all(fd, reinterpret_cast<const char*>(&header), sizeof header, deadline);
  write_all(fd, payload.bytes().data(), payload.bytes().size(), deadline);
}

Message receive(int fd, std::vector<char>& payload, Deadline deadline) {
  Header header;
  read_all(fd, reinterpret_cast<char*>(&header), sizeof header, deadline);
  if (header.magic != kMagic || header.size > kMaxPayload)
    throw ChannelClosed("sent bytes that are no message");
  payload.resize(header.size);
  read_all(fd, payload.data(), payload.size(), deadline);
  return header.type;
}

}  // namespace heightmarch::glsl_protocol
