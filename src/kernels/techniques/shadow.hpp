#pragma once
// Soft self-shadowing (the "Parallax Occlusion Mapping in GLSL" tutorial's parallaxSoftShadowMultiplier) from
// the POM hit, with the layer spec evaluated at L.z. Kept as the tutorial wrote it, including its texture
// step of s L.xy / L.z / N while the layer height is the hit depth / N: the samples run ahead of the light
// ray by a factor 1 / depth. The exact reference shows what that costs.
#include "kernels/techniques/pom.hpp"
#include "simd/isa_packets.hpp"

namespace heightmarch::HEIGHTMARCH_ISA_NS {

// The tutorial's soft shadow factor towards the light from a hit (its uv and depth, and its
// samples go on counting) into hit.shadow: any technique's hit can be shadowed by it.
template <int W, Addressing ADDRESSING, Filter FILTER>
void soft_shadow(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, HitPacket<W>& hit) {
  using F = vfloat<W>;
  using B = vbool<W>;
  const float* light = k.params.light;
  if (!(light[2] > 0.0f)) return;  // the tutorial's factor 1 for a light below the plane
  const F num_layers = k.layer_count(F(light[2]));
  const F layer_height = hit.depth / num_layers;
  const F tex_step_u = F(k.params.scale) * F(light[0]) / F(light[2]) / num_layers;
  const F tex_step_v = F(k.params.scale) * F(light[1]) / F(light[2]) / num_layers;
  F current_layer_height = hit.depth - layer_height;
  F u = hit.u + tex_step_u;
  F v = hit.v + tex_step_v;
  F height_from_texture = k.sample(u, v, B::all_true(), hit.samples);
  F shadow_multiplier(0.0f);
  B under_surface{};  // value-initialised: no lane under the surface yet
  const vint<W> bound = k.step_bound(num_layers);
  B active = current_layer_height > F(0.0f);
  for (int step_index = 1; step_index <= k.max_step_bound() && any(active); ++step_index) {
    const B below = active & (height_from_texture < current_layer_height);
    const F new_multiplier =
        (current_layer_height - height_from_texture) * (F(1.0f) - F(float(step_index)) / num_layers);
    shadow_multiplier = select(below, max(shadow_multiplier, new_multiplier), shadow_multiplier);
    under_surface = under_surface | below;
    // Every lane moves on (see march_layers); only active lanes record what they find.
    current_layer_height = current_layer_height - layer_height;
    u = u + tex_step_u;
    v = v + tex_step_v;
    height_from_texture = k.sample(u, v, active, hit.samples);
    active = active & (current_layer_height > F(0.0f)) & (vint<W>(step_index) < bound);
  }
  hit.shadow = select(under_surface, F(1.0f) - shadow_multiplier, F(1.0f));
}

template <int W, Addressing ADDRESSING, Filter FILTER>
HitPacket<W> shadow(KernelContext<W, ADDRESSING, Taps::memory, FILTER>& k, const RayPacket<W>& ray) {
  HitPacket<W> hit = pom(k, ray);
  soft_shadow(k, hit);
  return hit;
}

}  // namespace heightmarch::HEIGHTMARCH_ISA_NS
