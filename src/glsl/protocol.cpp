#include "glsl/protocol.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <system_error>

#include "heightmarch/error.hpp"

namespace heightmarch::glsl_protocol {

namespace {

// TechniqueParams on the wire: every field as a plain integer or float.
struct WireParams {
  std::int32_t technique = 0;
  float min_layers = 0, max_layers = 0, scale = 0;
  std::int32_t wrap = 0;
  std::int32_t filter = 0;
  std::uint8_t discard = 0;
  float light[3] = {};
  std::int32_t refine = 0;  // resolved: the registry's default where none was given
};

// The fields in wire order, once for both directions (Writer::value takes const&, Reader::value &).
template <class Io, class Wire>
void wire_fields(Io& io, Wire& p) {
  io.value(p.technique);
  io.value(p.min_layers);
  io.value(p.max_layers);
  io.value(p.scale);
  io.value(p.wrap);
  io.value(p.filter);
  io.value(p.discard);
  for (auto& l : p.light) io.value(l);
  io.value(p.refine);
}

TechniqueParams read_params(Reader& r) {
  WireParams wire;
  wire_fields(r, wire);
  if (wire.discard > 1) throw BadMessage("discard flag " + std::to_string(wire.discard) + " is not 0 or 1");
  TechniqueParams params;
  params.technique = Technique(wire.technique);
  params.layers = {wire.min_layers, wire.max_layers};
  params.scale = wire.scale;
  params.wrap = Wrap(wire.wrap);
  params.filter = Filter(wire.filter);
  params.discard = wire.discard != 0;
  std::copy(std::begin(wire.light), std::end(wire.light), params.light);
  params.refine = wire.refine;
  check(params);  // the command line's check: nothing here is acted on before it passed
  return params;
}

DepthMap read_map(Reader& r) {
  DepthMap map;
  r.value(map.width);
  r.value(map.height);
  r.array(map.texels);
  check_depth_map(map, "the depth map of a prepare request");
  return map;
}

DrawnRays read_rays(Reader& r) {
  DrawnRays drawn;
  for (auto* a : ray_arrays(drawn.rays)) r.array(*a);
  check_rays(drawn.rays);
  r.value(drawn.row_width);
  r.array(drawn.turn_u);
  r.array(drawn.turn_v);
  r.array(drawn.drawn);
  const std::size_t n = drawn.rays.tx.size();
  if (drawn.turn_u.size() != n || drawn.turn_v.size() != n || drawn.drawn.size() != n)
    throw InputError("drawn rays whose turns or flags differ in length from the rays");
  if (drawn.row_width == 0 || n % drawn.row_width != 0)
    throw InputError("drawn rays of " + std::to_string(n) + " texels in rows of " +
                     std::to_string(drawn.row_width));
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::fabs(drawn.turn_u[i]) <= 1e6f && std::fabs(drawn.turn_v[i]) <= 1e6f) || drawn.drawn[i] > 1)
      throw InputError("drawn ray " + std::to_string(i + 1) +
                       ": turns not finite within 1e6, or a flag not 0 or 1");
  return drawn;
}

constexpr std::size_t kMaxPathBytes = 4096;  // PATH_MAX

}  // namespace

std::array<const std::vector<float>*, kRayArrays> ray_arrays(const RayBatch& rays) {
  return {&rays.tx,    &rays.ty,    &rays.vx,    &rays.vy,   &rays.vz,
          &rays.du_dx, &rays.dv_dx, &rays.du_dy, &rays.dv_dy};
}

std::array<std::vector<float>*, kRayArrays> ray_arrays(RayBatch& rays) {
  return {&rays.tx,    &rays.ty,    &rays.vx,    &rays.vy,   &rays.vz,
          &rays.du_dx, &rays.dv_dx, &rays.du_dy, &rays.dv_dy};
}

void write(Writer& w, const TechniqueParams& params) {
  WireParams wire;
  wire.technique = std::int32_t(params.technique);
  wire.min_layers = params.layers.min_layers;
  wire.max_layers = params.layers.max_layers;
  wire.scale = params.scale;
  wire.wrap = std::int32_t(params.wrap);
  wire.filter = std::int32_t(params.filter);
  wire.discard = params.discard ? 1 : 0;
  std::copy(std::begin(params.light), std::end(params.light), wire.light);
  wire.refine = params.refine_steps();
  wire_fields(w, wire);
}

void write(Writer& w, const DepthMap& map) {
  w.value(map.width);
  w.value(map.height);
  w.array(map.texels);
}

void write(Writer& w, const DrawnRays& drawn) {
  for (const auto* a : ray_arrays(drawn.rays)) w.array(*a);
  w.value(drawn.row_width);
  w.array(drawn.turn_u);
  w.array(drawn.turn_v);
  w.array(drawn.drawn);
}

void write(Writer& w, const HitBuffers& hits) {
  hits.for_each([&](HitChannel, const auto& values) { w.array(values); });
}

void read(Reader& r, HitBuffers& hits, std::size_t rays) {
  hits.for_each([&](HitChannel channel, auto& values) {
    r.array(values);
    if (values.size() != rays)
      throw BadMessage(std::string(info(channel).name) + " array of " + std::to_string(values.size()) +
                       " for " + std::to_string(rays) + " rays");
  });
}

namespace {

GlPath read_path(Reader& r) {
  std::uint32_t path = 0;
  r.value(path);
#define HEIGHTMARCH_GL_PATH_KNOWN(id, ...) \
  if (path == std::uint32_t(GlPath::id)) return GlPath::id;
  HEIGHTMARCH_GL_PATHS(HEIGHTMARCH_GL_PATH_KNOWN)
#undef HEIGHTMARCH_GL_PATH_KNOWN
  throw BadMessage("GL path " + std::to_string(path) + " is none of the list's");
}

}  // namespace

void write(Writer& w, const GlRenderer& renderer) {
  w.value(std::uint32_t(renderer.path));
  for (const std::string* s : {&renderer.device, &renderer.renderer, &renderer.version, &renderer.driver})
    w.text(*s);
  w.value(std::uint8_t(renderer.software));
}

void read(Reader& r, GlRenderer& renderer) {
  renderer.path = read_path(r);
  for (std::string* s : {&renderer.device, &renderer.renderer, &renderer.version, &renderer.driver})
    r.text(*s);
  std::uint8_t software = 0;
  r.value(software);
  renderer.software = software != 0;
}

void write(Writer& w, const std::vector<GlDevice>& devices) {
  w.value(std::uint64_t(devices.size()));
  for (const GlDevice& d : devices) {
    w.value(std::int32_t(d.index));
    for (const std::string* s : {&d.name, &d.extensions, &d.renderer, &d.version, &d.error}) w.text(*s);
  }
}

void read(Reader& r, std::vector<GlDevice>& devices) {
  std::uint64_t count = 0;
  r.value(count);
  constexpr std::uint64_t kMaxDevices = 64;  // what the worker lists at most (egl_context.cpp)
  if (count > kMaxDevices)
    throw BadMessage(std::to_string(count) + " devices, more than " + std::to_string(kMaxDevices));
  devices.resize(count);
  for (GlDevice& d : devices) {
    std::int32_t index = 0;
    r.value(index);
    d.index = index;
    for (std::string* s : {&d.name, &d.extensions, &d.renderer, &d.version, &d.error}) r.text(*s);
  }
}

Request read_request(Message type, const std::vector<char>& payload) {
  Reader reader(payload);
  switch (type) {
    case Message::prepare: {
      PrepareRequest request;
      request.params = read_params(reader);
      std::uint8_t map_sent = 0, rays_sent = 0;
      reader.value(map_sent);
      if (map_sent > 1) throw BadMessage("map flag " + std::to_string(map_sent) + " is not 0 or 1");
      if (map_sent) request.map = read_map(reader);
      reader.value(rays_sent);
      if (rays_sent > 1) throw BadMessage("rays flag " + std::to_string(rays_sent) + " is not 0 or 1");
      if (rays_sent) request.rays = read_rays(reader);
      reader.text(request.shader_path);
      reader.finish();
      if (request.shader_path.size() > kMaxPathBytes || request.shader_path.find('\0') != std::string::npos)
        throw InputError("a shader path of " + std::to_string(request.shader_path.size()) +
                         " bytes that is no file name");
      return request;
    }
    case Message::draw:
      reader.finish();
      return DrawRequest{};
    case Message::read:
      reader.finish();
      return ReadRequest{};
    default:
      throw BadMessage("message type " + std::to_string(unsigned(type)) + " is no request");
  }
}

namespace {

// A payload grows by at most this much (or by what it holds, if more) before its bytes have come.
constexpr std::size_t kPayloadStep = std::size_t(1) << 20;

bool known(Message type) {
  return unsigned(type) >= unsigned(Message::ready) && unsigned(type) <= unsigned(Message::devices);
}

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

// Reads up to n bytes; fewer only at EOF.
std::size_t read_all(int fd, char* data, std::size_t n, Deadline deadline) {
  std::size_t got = 0;
  // Every pass reads at least one byte, or ends at EOF, or throws.
  while (got < n) {
    if (!wait_for(fd, POLLIN, deadline)) throw ChannelTimeout("timed out reading");
    const ssize_t done = ::read(fd, data + got, n - got);
    if (done < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (done < 0 && errno == ECONNRESET) break;
    if (done < 0) throw std::system_error(errno, std::generic_category(), "read");
    if (done == 0) break;
    got += std::size_t(done);
  }
  return got;
}

}  // namespace

void send(int fd, Message type, const Writer& payload, Deadline deadline) {
  Header header;
  header.type = type;
  header.size = payload.bytes().size();
  write_all(fd, reinterpret_cast<const char*>(&header), sizeof header, deadline);
  write_all(fd, payload.bytes().data(), payload.bytes().size(), deadline);
}

Message receive(int fd, std::vector<char>& payload, Deadline deadline, std::uint64_t max_payload) {
  // The header's fields as bytes: a type is compared as a number before it is taken as a Message.
  char bytes[sizeof(Header)];
  const std::size_t got = read_all(fd, bytes, sizeof bytes, deadline);
  if (got == 0) throw ChannelClosed("channel closed");
  if (got < sizeof bytes) throw BadMessage("the channel closed inside a message header");
  std::uint32_t magic = 0, type = 0;
  std::uint64_t size = 0;
  std::memcpy(&magic, bytes + offsetof(Header, magic), sizeof magic);
  std::memcpy(&type, bytes + offsetof(Header, type), sizeof type);
  std::memcpy(&size, bytes + offsetof(Header, size), sizeof size);
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%08x", unsigned(magic));
  if (magic != kMagic) throw BadMessage(std::string("bytes that are no message (magic ") + hex + ")");
  if (!known(Message(type))) throw BadMessage("a message of unknown type " + std::to_string(type));
  // A message of one step or less costs no more than the reader's buffers: always read.
  if (size > kPayloadStep && size > max_payload)
    throw BadMessage("a message of " + std::to_string(size) + " bytes, more than the " +
                     std::to_string(max_payload) + " its reader's memory budget leaves");
  payload.clear();
  // Each pass reads a step's worth, so memory follows the bytes that came, not the header's claim.
  while (payload.size() < size) {
    const std::size_t at = payload.size();
    const std::size_t step = std::size_t(std::min<std::uint64_t>(size - at, std::max(kPayloadStep, at)));
    payload.resize(at + step);
    const std::size_t read = read_all(fd, payload.data() + at, step, deadline);
    if (read < step)
      throw BadMessage("the channel closed after " + std::to_string(at + read) + " of a message's " +
                       std::to_string(size) + " bytes");
  }
  return Message(type);
}

}  // namespace heightmarch::glsl_protocol
