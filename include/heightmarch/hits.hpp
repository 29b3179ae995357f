#pragma once
// What a technique returns per ray, in the order of the RayBatch it traced: its outputs, one row
// each, and the only list of them. HitBuffers, the kernels' packets and the pointers that cross
// the dispatch boundary (src/kernels/kernel_abi.hpp), the kernels' stores, the GLSL harness's
// outputs and their read-back, the GLSL worker's messages, the check of an ISA or a GLSL draw
// against another, the measures (metrics.hpp) and the per-ray files all derive from these rows.
//
// Adding an output: its row here; the techniques that write it say so in their registry row
// (`writes`, technique_list.hpp) and set it in their kernel and GLSL function.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace heightmarch {

// X(name, element type, value where nothing writes it, writer, measured against, label)
// - writer: `hit`, every technique's kernel and GLSL program; `optional`, the techniques whose
//   registry row's `writes` names it (the others leave its initial value); `loop`, the packet
//   loop around a kernel and the GLSL read-back (from the other outputs); `exact_pass`, the exact
//   reference's float pass alone (its own output, kept by the reference: no HitBuffers holds it).
// - measured against: `hit`, the exact hit (the uv and depth errors); `visibility`, the exact
//   visibility of the light from the exact hit (the exact reference walks the light where a
//   technique writes such an output; measures NAME_error_mean and NAME_mismatch_rate); `none`.
#define HEIGHTMARCH_HIT_CHANNELS(X)                                                                 \
  X(u, float, 0.0f, hit, hit, "u")                                                                  \
  X(v, float, 0.0f, hit, hit, "v")                                                                  \
  X(depth, float, 0.0f, hit, hit, "depth")                                                          \
  X(samples, std::uint32_t, 0, hit, none, "height samples taken (exact: texel cells solved)")       \
  X(shadow, float, 1.0f, optional, visibility, "shadow factor") /* exact: the visibility, 0 or 1 */ \
  X(discarded, std::uint8_t, 0, loop, none, "discarded (--discard: final uv outside [0,1]^2)")      \
  X(settled, std::uint8_t, 0, exact_pass, none, "settled by the exact reference's float pass")      \
  X(clear_depth, float, 0.0f, exact_pass, none, "depth to which the exact path is clear")

enum class ChannelWriter { hit, optional, loop, exact_pass };
enum class MeasuredAgainst { hit, visibility, none };

#define HEIGHTMARCH_HIT_CHANNEL_ENUM(name, ...) name,
enum class HitChannel { HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_CHANNEL_ENUM) };
#undef HEIGHTMARCH_HIT_CHANNEL_ENUM

#define HEIGHTMARCH_HIT_CHANNEL_COUNT(...) +1
inline constexpr int kHitChannelCount = 0 HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_CHANNEL_COUNT);
#undef HEIGHTMARCH_HIT_CHANNEL_COUNT

struct HitChannelInfo {
  HitChannel id;
  std::string_view name;
  double initial;
  ChannelWriter writer;
  MeasuredAgainst against;
  std::string_view label;
};

constexpr std::array<HitChannelInfo, kHitChannelCount> hit_channels() {
#define HEIGHTMARCH_HIT_CHANNEL_INFO(name, type, initial, writer, against, label)         \
  HitChannelInfo{HitChannel::name,         #name, double(initial), ChannelWriter::writer, \
                 MeasuredAgainst::against, label},
  return {HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_CHANNEL_INFO)};
#undef HEIGHTMARCH_HIT_CHANNEL_INFO
}
constexpr HitChannelInfo info(HitChannel channel) { return hit_channels()[std::size_t(channel)]; }

// HEIGHTMARCH_IN_HITS_<writer>(...): its arguments for a row HitBuffers holds, nothing otherwise.
#define HEIGHTMARCH_IN_HITS_hit(...) __VA_ARGS__
#define HEIGHTMARCH_IN_HITS_optional(...) __VA_ARGS__
#define HEIGHTMARCH_IN_HITS_loop(...) __VA_ARGS__
#define HEIGHTMARCH_IN_HITS_exact_pass(...)

// A technique's outputs for a batch: one array per row but the exact pass's.
struct HitBuffers {
#define HEIGHTMARCH_HIT_BUFFER(name, type, initial, writer, ...) \
  HEIGHTMARCH_IN_HITS_##writer(std::vector<type> name;)
  HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_BUFFER)
#undef HEIGHTMARCH_HIT_BUFFER

  // Calls f(channel, array) for each array, in the list's order.
  template <class F>
  void for_each(F&& f) {
    visit(*this, f);
  }
  template <class F>
  void for_each(F&& f) const {
    visit(*this, f);
  }
  // Calls f(channel, a's array, b's array) for each array of two batches' hits.
  template <class F>
  static void for_each_pair(const HitBuffers& a, const HitBuffers& b, F&& f) {
#define HEIGHTMARCH_HIT_PAIR(name, type, initial, writer, ...) \
  HEIGHTMARCH_IN_HITS_##writer(f(HitChannel::name, a.name, b.name);)
    HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_PAIR)
#undef HEIGHTMARCH_HIT_PAIR
  }

  // Sized for n rays, each array at its initial value; the kernels write every element, so
  // same-size reuse does not refill.
  void resize(std::size_t n) {
    if (size() == n) return;
#define HEIGHTMARCH_HIT_ASSIGN(name, type, initial, writer, ...) \
  HEIGHTMARCH_IN_HITS_##writer(name.assign(n, type(initial));)
    HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_ASSIGN)
#undef HEIGHTMARCH_HIT_ASSIGN
  }
  std::size_t size() const { return u.size(); }

 private:
  template <class Self, class F>
  static void visit(Self& self, F& f) {
#define HEIGHTMARCH_HIT_VISIT(name, type, initial, writer, ...) \
  HEIGHTMARCH_IN_HITS_##writer(f(HitChannel::name, self.name);)
    HEIGHTMARCH_HIT_CHANNELS(HEIGHTMARCH_HIT_VISIT)
#undef HEIGHTMARCH_HIT_VISIT
  }
};

}  // namespace heightmarch
