#pragma once
// How a batch is filled, tile by tile (ray_batch.cpp's ray lists, views.cpp's views): one ray as a
// camera or a list gives it, and the builder that appends rays and pads each tile.
#include <algorithm>
#include <cstdint>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/rays.hpp"

namespace heightmarch {

struct Ray {
  bool hit;
  float tx, ty, vx, vy, vz;
  std::uint32_t view = 0;  // of its set (RayBatch::view)
};

// Appends one tile's rays, padded with copies of its last ray to a multiple of kRayAlignment.
class BatchBuilder {
 public:
  explicit BatchBuilder(RayBatch& batch) : batch_(batch) {}
  void add(const Ray& r, std::uint32_t origin) {
    batch_.tx.push_back(r.tx);
    batch_.ty.push_back(r.ty);
    batch_.vx.push_back(r.vx);
    batch_.vy.push_back(r.vy);
    batch_.vz.push_back(r.vz);
    for (auto* g : {&batch_.du_dx, &batch_.dv_dx, &batch_.du_dy, &batch_.dv_dy}) g->push_back(0.0f);
    batch_.origin.push_back(origin);
    batch_.view.push_back(r.view);
    batch_.views = std::max(batch_.views, r.view + 1);
    ++batch_.ray_count;
  }
  void end_tile() {
    const std::size_t begin = batch_.tile_offsets.back();
    if (batch_.size() == begin) return;  // no ray in this tile
    while (batch_.size() % kRayAlignment != 0) {
      const std::size_t last = batch_.size() - 1;
      add({true, batch_.tx[last], batch_.ty[last], batch_.vx[last], batch_.vy[last], batch_.vz[last],
           batch_.view[last]},
          kPaddingRay);
      --batch_.ray_count;
    }
    batch_.tile_offsets.push_back(batch_.size());
  }

 private:
  RayBatch& batch_;
};

inline void check_tile_size(int tile_size) {
  if (tile_size < 1 || tile_size > 4096)
    throw InputError("tile size " + std::to_string(tile_size) + " outside [1, 4096]");
}

}  // namespace heightmarch
