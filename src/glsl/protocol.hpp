#pragma once
// What the GLSL client (glsl_runner.cpp, in heightmarch_core) and heightmarch-glsl-worker
// (worker_main.cpp) say to each other over the worker's stdin/stdout, a socket pair.
//
// A message is a Header and `size` bytes of payload: plain values and length-prefixed arrays in
// host byte order (both ends are the same build on the same machine). The client sends one
// request and reads its answers:
//   (at start)                  -> ready {u32 protocol version, GlRenderer}
//   prepare {params, u8 map follows, [map], u8 rays follow, [drawn rays: T, V and the gradients
//            a texel each, u32 row width, the turns' two arrays, u8 array drawn], shader path}
//                               -> compiled (the program is linked), then done (uploaded)
//                               (a map or rays not sent: the worker's last ones, unchanged)
//   draw                        -> drawn {f64 seconds of draw + glFinish, timed in the worker,
//                                  u8 timer query answered, f64 its seconds}
//   read                        -> hits {HitBuffers' arrays in the list's order (hits.hpp), u8 samples known}
// and any request may be answered input_error {text} (an InputError: the same one-line message)
// or error {text} (anything else; the worker stays usable after both). Started to answer one
// question instead (heightmarch-glsl-worker --paths, --list-devices), it sends one message and exits:
//   paths {u32 protocol version, u32 array: the GL paths it was built with}
//   devices {u32 protocol version, u64 count, GlDevice each}
//
// Each end trusts nothing it reads: a message is refused (BadMessage) for a wrong magic, an
// unknown type, a payload larger than what the reader's memory budget leaves (checked before it
// allocates anything; a payload is then read piece by piece, so a header that lies about its size
// costs only the bytes that came) or fields that do not fit it; the worker checks every field of
// a request with the checks the command line uses (read_request) before it acts on any.
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "glsl/screen_layout.hpp"
#include "heightmarch/gl_target.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/hits.hpp"
#include "heightmarch/rays.hpp"
#include "heightmarch/technique.hpp"

namespace heightmarch::glsl_protocol {

inline constexpr std::uint32_t kVersion = 7;
inline constexpr std::uint32_t kMagic = 0x4c474d48;  // "HMGL": a stray write to stdout is caught at once
// The worker's exit status when an allocation failed outside a request (reading one, starting).
inline constexpr int kOutOfMemoryStatus = 3;

enum class Message : std::uint32_t {
  ready = 1,
  prepare,
  done,
  draw,
  drawn,
  read,
  hits,
  input_error,
  error,
  compiled,
  paths,
  devices
};

struct Header {
  std::uint32_t magic = kMagic;
  Message type = Message::error;
  std::uint64_t size = 0;
};

// The other end closed the channel between two messages (it exited, crashed or is done).
struct ChannelClosed : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Bytes that are no message of this protocol, or a message whose fields do not fit its payload.
struct BadMessage : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// No whole message before the deadline.
struct ChannelTimeout : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Writer {
 public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    append(&v, sizeof v);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(std::uint64_t(v.size()));
    append(v.data(), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    value(std::uint64_t(s.size()));
    append(s.data(), s.size());
  }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  void append(const void* data, std::size_t n) {
    // resize + memcpy: GCC 12 takes vector::insert of a few bytes for an overflow (-Wstringop-overflow).
    const std::size_t at = bytes_.size();
    bytes_.resize(at + n);
    if (n) std::memcpy(bytes_.data() + at, data, n);
  }
  std::vector<char> bytes_;
};

// Reads a payload back; a short or overlong payload throws BadMessage. Values are read as the
// integers and floats they are on the wire: an enum or a bool is never read from raw bytes.
class Reader {
 public:
  explicit Reader(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <class T>
  void value(T& v) {
    static_assert(std::is_arithmetic_v<T>);
    std::memcpy(&v, take(sizeof v), sizeof v);
  }
  template <class T>
  void array(std::vector<T>& v) {
    static_assert(std::is_arithmetic_v<T>);
    std::uint64_t n = 0;
    value(n);
    if (n > (bytes_.size() - at_) / sizeof(T)) throw BadMessage("message array longer than its payload");
    v.resize(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
  }
  void text(std::string& s) {
    std::uint64_t n = 0;
    value(n);
    if (n > bytes_.size() - at_) throw BadMessage("message text longer than its payload");
    s.assign(take(n), n);
  }
  void finish() const {
    if (at_ != bytes_.size()) throw BadMessage("message payload longer than its fields");
  }

 private:
  const char* take(std::size_t n) {
    if (n > bytes_.size() - at_) throw BadMessage("message payload shorter than its fields");
    const char* p = bytes_.data() + at_;
    at_ += n;
    return p;
  }
  const std::vector<char>& bytes_;
  std::size_t at_ = 0;
};

// The arrays of a batch the GL run reads, in wire order: T, V and the gradients.
inline constexpr std::size_t kRayArrays = 9;
std::array<const std::vector<float>*, kRayArrays> ray_arrays(const RayBatch& rays);
std::array<std::vector<float>*, kRayArrays> ray_arrays(RayBatch& rays);

// The one place that knows TechniqueParams' fields (params_fields in protocol.cpp, for both directions).
void write(Writer& w, const TechniqueParams& params);
void write(Writer& w, const DepthMap& map);
// The rays of a draw laid out (screen_layout.hpp): T, V and the gradients of each texel, its row
// width, the turns and the drawn flags; all the GL run reads.
void write(Writer& w, const DrawnRays& rays);
void write(Writer& w, const HitBuffers& hits);
// Hits as the worker answers them, for `rays` rays: arrays of that length, or BadMessage.
void read(Reader& r, HitBuffers& hits, std::size_t rays);
// What the worker's context is (ready), and EGL's devices (devices); BadMessage for a path that
// is none of the list's.
void write(Writer& w, const GlRenderer& renderer);
void read(Reader& r, GlRenderer& renderer);
void write(Writer& w, const std::vector<GlDevice>& devices);
void read(Reader& r, std::vector<GlDevice>& devices);

// The requests the worker serves, read and checked whole before it acts on any.
struct PrepareRequest {
  TechniqueParams params;
  std::optional<DepthMap> map;    // none: the worker's last one
  std::optional<DrawnRays> rays;  // none: the worker's last ones
  std::string shader_path;        // a brought-in shader's file, or empty
};
struct DrawRequest {};
struct ReadRequest {};
using Request = std::variant<PrepareRequest, DrawRequest, ReadRequest>;

// The worker's message reader: BadMessage for a type that is no request or fields that do not fit
// the payload, InputError for a value the command line would refuse (check(TechniqueParams),
// check_depth_map, check_rays, and drawn rays whose arrays differ in length, fill no whole rows, or
// hold turns not finite within 1e6 or flags other than 0 and 1; a shader path that is no path).
Request read_request(Message type, const std::vector<char>& payload);

using Deadline = std::optional<std::chrono::steady_clock::time_point>;  // none: wait for EOF at most

void send(int fd, Message type, const Writer& payload, Deadline deadline);
// Throws ChannelClosed on EOF before a header, BadMessage on anything that is no message (EOF
// inside one included) or a payload of more than max_payload bytes (what the reader's budget
// leaves; a payload of up to 1 MiB is always read), ChannelTimeout after the deadline.
Message receive(int fd, std::vector<char>& payload, Deadline deadline, std::uint64_t max_payload);

}  // namespace heightmarch::glsl_protocol
