#pragma once
// Measures the figures the claims' rules read: every technique and layer spec of
// claim_layer_specs() on the default view of each heightfield, and plain and offset-limited
// parallax on sweep views at claim_sweep_angles().
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "heightmarch/claims.hpp"
#include "heightmarch/isa.hpp"

namespace heightmarch {

struct ClaimsSetup {
  std::vector<std::string> heightfields;  // "builtin:NAME" or paths
  int resolution = 512;                    // of builtin heightfields
  std::uint64_t seed = 1;
  int view_size = 512;                     // default view side, pixels
  int sweep_size = 256;                    // sweep view side, pixels
  Isa isa = Isa::scalar;
  double min_seconds = 0.05;               // timing per configuration (rays/s for C8, C9)
  std::function<void(const std::string&)> progress;  // called before each heightfield
};

ClaimsData measure_claims(const ClaimsSetup& setup);

// "bricks" for "builtin:bricks", the file name without directories otherwise.
std::string heightfield_label(const std::string& spec);

}  // namespace heightmarch
