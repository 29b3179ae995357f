#pragma once
// The techniques: one row each, and the only list of them. The enum, CLI names and help, each
// ISA's kernel table, the GLSL entry point, the textures a run builds, the measures a run takes,
// benchmarks, the suite plan, test parameters and the report's palette all derive from these rows.
//
// Adding a technique takes three files: its row here, its kernel header in
// src/kernels/techniques/ (every header there is compiled into every ISA's kernel table) and its
// GLSL function in src/glsl/techniques.glsl; two for one made of existing steps, whose GLSL call
// composes them (softShadow(cone(T, V))).
//
// X(id, CLI name, layered, refine, needs, writes, search, shape, kernel, GLSL call, plot colour,
//   plot marker, description)
// - layered: takes a layer spec; otherwise one sample ("1").
// - refine: its default --refine (ignored by those that do not refine).
// - needs: the precomputed textures it reads besides the depth map (Needs, technique.hpp),
//   built once per depth map and wrap for the CPU and GLSL alike.
// - writes: Writes::hit, or the optional outputs it writes besides its hit (heightmarch/hits.hpp):
//   Writes::shadow for a shadow factor (measured against the exact visibility of the light).
// - search: one of the searches the suite times at every ISA and thread count.
// - shape: KernelShape::march (a layered march: an ISA may run two packets in flight) or
//   KernelShape::walk (a divergent walk: its own packets in flight and event lanes per ISA).
// - kernel: its packet kernel in src/kernels/techniques/, called as kernel(k, ray) with the
//   KernelContext and a RayPacket, returning a HitPacket (each ISA's table calls it); a walk's as
//   kernel(k, ray, walk) with its rays' PyramidWalk, after its WalkSteps queued them.
// The GLSL call is evaluated with `T` and `V` in scope. Colours and markers are the report's,
// one per technique everywhere.
#define HEIGHTMARCH_TECHNIQUES(X)                                                                            \
  X(parallax, "parallax", false, 5, Needs::nothing, Writes::hit, false, KernelShape::march, parallax<false>, \
    "parallax(T, V, false)", "#7f7f7f", "v", "plain parallax: one sample, uv = T - V.xy / V.z * D(T) s")     \
  X(parallax_limited, "parallax-limited", false, 5, Needs::nothing, Writes::hit, false, KernelShape::march,  \
    parallax<true>, "parallax(T, V, true)", "#bcbd22", "^",                                                  \
    "offset limiting: one sample, uv = T - V.xy * D(T) s")                                                   \
  X(steep, "steep", true, 5, Needs::nothing, Writes::hit, true, KernelShape::march, steep<false>,            \
    "steep(T, V, false)", "#1f77b4", "o",                                                                    \
    "steep parallax: layers of depth 1/N, stop at the first below the surface")                              \
  X(steep_limited, "steep-limited", true, 5, Needs::nothing, Writes::hit, false, KernelShape::march,         \
    steep<true>, "steep(T, V, true)", "#17becf", "D",                                                        \
    "steep parallax stepping s V.xy / N (no division by V.z)")                                               \
  X(relief, "relief", true, 5, Needs::nothing, Writes::hit, true, KernelShape::march, relief,                \
    "relief(T, V)", "#2ca02c", "P", "relief mapping: steep, then binary search between the last two layers") \
  X(pom, "pom", true, 5, Needs::nothing, Writes::hit, true, KernelShape::march, pom, "pom(T, V)", "#d62728", \
    "s", "parallax occlusion mapping: steep, then linear interpolation between the last two layers")         \
  X(secant, "secant", true, 5, Needs::nothing, Writes::hit, true, KernelShape::march, secant,                \
    "secant(T, V)", "#ff7f0e", "X",                                                                          \
    "secant (interval) mapping: steep, then --refine regula falsi steps between the last two layers")        \
  X(cone, "cone", true, 4, Needs::cone_map, Writes::hit, true, KernelShape::march, cone, "cone(T, V)",       \
    "#e377c2", "p",                                                                                          \
    "relaxed cone stepping: N steps to the relaxed cone's edge, then --refine halvings of the bracket")      \
  X(maxmip, "maxmip", false, 5, Needs::min_depth_pyramid, Writes::hit, true, KernelShape::walk, maxmip,      \
    "maxmip(T, V)", "#8c564b", "h",                                                                          \
    "maximum mipmaps: walk down and up the min-depth pyramid, solve each reached cell exactly")              \
  X(shadow, "shadow", true, 5, Needs::nothing, Writes::shadow, false, KernelShape::march, shadow,            \
    "softShadow(pom(T, V))", "#9467bd", "*",                                                                 \
    "POM's hit, then the tutorial's soft self-shadow factor towards the light")
