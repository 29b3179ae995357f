#pragma once
// The byte shuffles that move the lanes of a 4-wide packet for expand_load() and compress_store()
// (packet.hpp), for ISAs with a byte-table shuffle: SSE's pshufb and NEON's tbl pick the same
// bytes for indices 0 to 15.
#include <cstdint>

#include "simd/packet.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// For each mask of 4 lanes, the controls that move element k of a load to the k-th true lane
// (expand: the bytes of lane l are those of the number of true lanes below l) and the k-th true
// lane to element k (compress).
struct LaneShuffles4 {
  alignas(16) std::uint8_t expand[16][16] = {};
  alignas(16) std::uint8_t compress[16][16] = {};
  constexpr LaneShuffles4() {
    for (int mask = 0; mask < 16; ++mask)
      for (int lane = 0, below = 0; lane < 4; ++lane) {
        for (int byte = 0; byte < 4; ++byte) {
          expand[mask][4 * lane + byte] = std::uint8_t(4 * below + byte);
          if ((mask >> lane) & 1) compress[mask][4 * below + byte] = std::uint8_t(4 * lane + byte);
        }
        below += (mask >> lane) & 1;
      }
  }
};
inline constexpr LaneShuffles4 kLaneShuffles4{};

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
