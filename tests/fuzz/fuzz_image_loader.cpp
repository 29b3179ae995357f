// libFuzzer: any bytes as a depth map file (OpenImageIO picks the reader by content) give a
// depth map with finite texels in [0, 1] or an InputError.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/heightmarch-fuzz-image-" + std::to_string(::getpid());
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const heightmarch::DepthMap map = heightmarch::load_depth_map(path);
    if (map.width < 1 || map.height < 1 ||
        map.texels.size() != std::size_t(map.width) * std::size_t(map.height))
      __builtin_trap();
    for (float d : map.texels)
      if (!(d >= 0.0f && d <= 1.0f)) __builtin_trap();
  } catch (const heightmarch::InputError&) {
  }
  return 0;
}
