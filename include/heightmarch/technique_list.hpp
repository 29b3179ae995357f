#pragma once
// The techniques: one row each, and the only list of them. The enum, CLI names and help, each
// ISA's kernel table, the GLSL entry point, benchmarks, the suite plan, test parameters and the
// report's palette all derive from these rows.
//
// Adding a technique: its kernel header (src/kernels/, included below for the kernel
// translation units), its GLSL function (src/glsl/techniques.glsl), and one row here.
//
// X(id, CLI name, layered, refine, CPU kernel call, GLSL call, plot colour, plot marker, description)
// `refine` is the technique's default --refine (ignored by those that do not refine). The CPU
// call is evaluated with `k` (the KernelContext) and `ray` (the RayPacket) in scope; the GLSL
// call with `T` and `V`. Colours and markers are the report's, one per technique everywhere.
#define HEIGHTMARCH_TECHNIQUES(X)                                                                       \
  X(parallax, "parallax", false, 5, parallax<false>(k, ray), "parallax(T, V, false)", "#7f7f7f", "v",   \
    "plain parallax: one sample, uv = T - V.xy / V.z * D(T) s")                                         \
  X(parallax_limited, "parallax-limited", false, 5, parallax<true>(k, ray), "parallax(T, V, true)",     \
    "#bcbd22", "^", "offset limiting: one sample, uv = T - V.xy * D(T) s")                              \
  X(steep, "steep", true, 5, steep<false>(k, ray), "steep(T, V, false)", "#1f77b4", "o",                \
    "steep parallax: layers of depth 1/N, stop at the first below the surface")                         \
  X(steep_limited, "steep-limited", true, 5, steep<true>(k, ray), "steep(T, V, true)", "#17becf", "D",  \
    "steep parallax stepping s V.xy / N (no division by V.z)")                                          \
  X(relief, "relief", true, 5, relief(k, ray), "relief(T, V)", "#2ca02c", "P",                          \
    "relief mapping: steep, then binary search between the last two layers")                            \
  X(pom, "pom", true, 5, pom(k, ray), "pom(T, V)", "#d62728", "s",                                      \
    "parallax occlusion mapping: steep, then linear interpolation between the last two layers")         \
  X(secant, "secant", true, 5, secant(k, ray), "secant(T, V)", "#ff7f0e", "X",                          \
    "secant (interval) mapping: steep, then --refine regula falsi steps between the last two layers")   \
  X(cone, "cone", true, 4, cone(k, ray), "cone(T, V)", "#e377c2", "p",                                  \
    "relaxed cone stepping: N steps to the relaxed cone's edge, then --refine halvings of the bracket") \
  X(maxmip, "maxmip", false, 5, maxmip(k, ray), "maxmip(T, V)", "#8c564b", "h",                         \
    "maximum mipmaps: walk down and up the min-depth pyramid, solve each reached cell exactly")         \
  X(shadow, "shadow", true, 5, shadow(k, ray), "shadow(T, V)", "#9467bd", "*",                          \
    "POM's hit, then the tutorial's soft self-shadow factor towards the light")

#ifdef HEIGHTMARCH_ISA_NS  // a kernel translation unit (src/isa/): every technique's kernel
#include "kernels/cone.hpp"
#include "kernels/maxmip.hpp"
#include "kernels/parallax.hpp"
#include "kernels/pom.hpp"
#include "kernels/relief.hpp"
#include "kernels/secant.hpp"
#include "kernels/shadow.hpp"
#include "kernels/steep.hpp"
#endif
