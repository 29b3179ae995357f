#pragma once
// Where the GLSL draws a batch's rays (docs/techniques.md#the-gl-paths): a view's rays at their
// pixels, each frame of a set in its own region, so the fragments of a 2 x 2 quad are screen
// neighbours and a brought-in shader's texture() takes the derivatives a GPU would give it; a
// batch without a pixel grid (a rays file) in rows of kRowWidth in batch order, where texture()'s
// level of detail comes from unrelated rays.
#include <cstdint>
#include <vector>

#include "heightmarch/rays.hpp"

namespace heightmarch {

// The rays of one draw as the worker lays them out: one a texel, rows of row_width texels.
struct DrawnRays {
  RayBatch rays;  // T, V and the gradients, one a texel in row order: nothing else of a batch
  std::uint32_t row_width = 0;
  // Whole turns of the map a brought-in shader's T is given beside T (its uv given back less
  // them), under the repeat wrap: they keep T continuous over a quad where a set's view crosses
  // the map's edge (its entry points are taken modulo 1), as a GPU's interpolated texture
  // coordinate is. A builtin technique reads T alone.
  std::vector<float> turn_u, turn_v;
  // 1: a ray of the batch, or a helper (a quad's fragment where the view has no ray, its T and V
  // continued from a neighbour's by the neighbour's gradients, as a GPU's helper invocation
  // interpolates them); 0: a texel no quad needs, which the draw leaves at once.
  std::vector<std::uint8_t> drawn;
};

// A batch ray per texel of 1024 where the batch has no pixel grid.
inline constexpr int kRowWidth = 1024;

struct ScreenLayout {
  DrawnRays drawn;
  bool screen = false;                  // laid out as the view's pixels
  std::vector<std::uint32_t> texel_of;  // per ray of the batch (padding too): its texel
};

// The layout of a batch: as its pixels where it has a grid (frame_width > 0: each frame of its
// image at even offsets, so a quad never spans two), else in rows of kRowWidth. Asks the memory
// budget first.
ScreenLayout screen_layout(const RayBatch& rays);

}  // namespace heightmarch
