// libFuzzer: layer specs and techniques parse to a valid value or an InputError, nothing else.
#include <cstdint>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/technique.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const heightmarch::LayerSpec spec = heightmarch::parse_layer_spec(text);
    if (!(spec.min_layers >= 1 && spec.max_layers <= heightmarch::kMaxLayers &&
          spec.min_layers <= spec.max_layers))
      __builtin_trap();
  } catch (const heightmarch::InputError&) {
  }
  try {
    heightmarch::parse_technique(text);
  } catch (const heightmarch::InputError&) {
  }
  return 0;
}
