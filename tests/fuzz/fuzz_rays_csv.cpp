// libFuzzer: any bytes as a rays file give a valid batch (finite, unit V, V.z > 0) or an InputError.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/rays.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/heightmarch-fuzz-rays-" + std::to_string(::getpid()) + ".csv";
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  try {
    const heightmarch::RayBatch rays = heightmarch::load_rays_csv(path, 8);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double len = std::hypot(rays.vx[i], rays.vy[i], rays.vz[i]);
      if (!(rays.vz[i] > 0.0f) || !std::isfinite(rays.tx[i]) || !std::isfinite(rays.ty[i]) ||
          std::fabs(len - 1.0) > 1e-5)
        __builtin_trap();
    }
    if (rays.size() % heightmarch::kRayAlignment != 0) __builtin_trap();
  } catch (const heightmarch::InputError&) {
  }
  return 0;
}
