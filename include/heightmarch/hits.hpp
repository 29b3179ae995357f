#pragma once
// What a technique returns per ray, in the order of the RayBatch it traced.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace heightmarch {

struct HitBuffers {
  std::vector<float> u, v, depth;
  std::vector<std::uint32_t> samples;  // height samples taken (exact: texel cells solved)
  std::vector<float> shadow;           // shadow technique: soft shadow factor; exact: visibility 0/1
  std::vector<std::uint8_t> discarded; // --discard: final uv outside [0,1]^2

  // Sized for n rays; the kernels write every element, so same-size reuse does not refill.
  void resize(std::size_t n) {
    if (size() == n) return;
    u.assign(n, 0.0f);
    v.assign(n, 0.0f);
    depth.assign(n, 0.0f);
    samples.assign(n, 0);
    shadow.assign(n, 1.0f);
    discarded.assign(n, 0);
  }
  std::size_t size() const { return u.size(); }
};

}  // namespace heightmarch
