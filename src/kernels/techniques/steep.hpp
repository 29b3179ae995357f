#pragma once
// Steep parallax: the layer march alone; its hit is the first layer below the surface.
#include "kernels/layer_march.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

template <bool LIMITED, int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> steep(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  const LayerMarch<W> m = march_layers<LIMITED>(k, ray);
  HitPacket<W> hit;
  hit.u = m.u;
  hit.v = m.v;
  hit.depth = m.current_layer_depth;
  hit.samples = m.samples;
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
