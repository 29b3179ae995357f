// Each technique against a hand-traced example and against its defining property.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "heightmarch/exact.hpp"
#include "heightmarch/metrics.hpp"
#include "heightmarch/tracer.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

HitBuffers trace_with(const DepthMap& map, const RayBatch& rays, TechniqueParams params,
                      Isa isa = Isa::scalar) {
  HitBuffers hits;
  Tracer(map, params, isa).run(rays, hits);
  return hits;
}

TechniqueParams params_for(Technique technique, const std::string& layers, Wrap wrap = Wrap::repeat) {
  TechniqueParams p;
  p.technique = technique;
  p.layers = parse_layer_spec(layers);
  p.wrap = wrap;
  return p;
}

RayBatch one_ray(float tx, float ty, float vx, float vy, float vz) {
  return make_ray_list({tx}, {ty}, {vx}, {vy}, {vz});
}

// A plane tilted in u, D = (i + 0.5) / W: under CLAMP a ray crosses it exactly once.
DepthMap tilted_plane(int w) {
  DepthMap map{w, 4, {}};
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < w; ++i) map.texels.push_back((i + 0.5f) / float(w));
  return map;
}

TEST(Parallax, ClosedForm) {
  const DepthMap map = make_builtin_heightfield("terrain", 64, 3);
  const RayBatch rays = test::random_rays(500, 80.0, 11);
  for (bool limited : {false, true}) {
    const HitBuffers hits =
        trace_with(map, rays, params_for(limited ? Technique::parallax_limited : Technique::parallax, "1"));
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const float d = sample_depth(map, Wrap::repeat, rays.tx[i], rays.ty[i]);
      const float dir_x = limited ? rays.vx[i] : rays.vx[i] / rays.vz[i];
      const float dir_y = limited ? rays.vy[i] : rays.vy[i] / rays.vz[i];
      ASSERT_EQ(hits.u[i], rays.tx[i] - dir_x * (d * 0.1f));
      ASSERT_EQ(hits.v[i], rays.ty[i] - dir_y * (d * 0.1f));
      ASSERT_EQ(hits.samples[i], 1u);
    }
  }
}

TEST(Steep, HandTracedOnAFlatDepth) {
  // D = 0.3 everywhere, 10 layers: layer depths 0, 0.1, 0.2, 0.3000000119 (float sums); the loop
  // runs while layer < D, so it stops at the 3rd step with 4 samples, uv = T - 3 delta.
  const DepthMap map{8, 8, std::vector<float>(64, 0.3f)};
  const float vx = 0.6f, vy = 0.0f, vz = 0.8f;
  const HitBuffers hits =
      trace_with(map, one_ray(0.5f, 0.5f, vx, vy, vz), params_for(Technique::steep, "10"));
  const float delta = (vx / vz * 0.1f) / 10.0f;
  EXPECT_EQ(hits.samples[0], 4u);
  EXPECT_FLOAT_EQ(hits.depth[0], 0.3f);
  EXPECT_EQ(hits.u[0], 0.5f - delta - delta - delta);
  EXPECT_EQ(hits.v[0], 0.5f);
}

TEST(Steep, ErrorBelowOneLayer) {
  const DepthMap map = tilted_plane(64);
  const ExactIntersector exact(map, Wrap::clamp);
  for (bool limited : {false, true}) {
    const RayBatch rays = test::random_rays(400, 75.0, 5);
    const auto params = params_for(limited ? Technique::steep_limited : Technique::steep, "16", Wrap::clamp);
    const HitBuffers hits = trace_with(map, rays, params);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (limited) {
        // The limited step s V.xy / N leaves the true ray; its defining property is the stop:
        // the last layer is at or below the surface there, the one before it was above.
        const float delta = rays.vx[i] * 0.1f / 16.0f;
        ASSERT_GE(hits.depth[i] + 1e-6f, sample_depth(map, Wrap::clamp, hits.u[i], hits.v[i]));
        if (hits.samples[i] > 1) {
          ASSERT_LT(hits.depth[i] - 1.0f / 16.0f,
                    sample_depth(map, Wrap::clamp, hits.u[i] + delta, hits.v[i] + rays.vy[i] * 0.1f / 16.0f) +
                        1e-6f);
        }
        continue;
      }
      const double d = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.1).t;
      ASSERT_GE(hits.depth[i], d - 1e-6);
      ASSERT_LT(hits.depth[i], d + 1.0 / 16.0 + 1e-6);
    }
  }
}

TEST(Relief, WithinTheFinalBracket) {
  const DepthMap map = tilted_plane(64);
  const ExactIntersector exact(map, Wrap::clamp);
  const RayBatch rays = test::random_rays(400, 75.0, 6);
  for (int refine : {0, 3, 5, 8}) {
    auto params = params_for(Technique::relief, "8", Wrap::clamp);
    params.refine = refine;
    const HitBuffers hits = trace_with(map, rays, params);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double d = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.1).t;
      ASSERT_NEAR(hits.depth[i], d, (1.0 / 8.0) / std::pow(2.0, refine + 1) + 1e-6) << "refine " << refine;
      ASSERT_EQ(hits.samples[i] - refine,
                trace_with(map, rays, params_for(Technique::steep, "8", Wrap::clamp)).samples[i]);
    }
  }
}

TEST(Pom, HitLiesBetweenItsTwoLayers) {
  const DepthMap map = make_builtin_heightfield("waves", 128, 2);
  const RayBatch rays = test::random_rays(1000, 80.0, 8);
  const HitBuffers steep = trace_with(map, rays, params_for(Technique::steep, "16"));
  const HitBuffers pom = trace_with(map, rays, params_for(Technique::pom, "16"));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    // POM re-reads the previous layer: one sample more than steep.
    ASSERT_EQ(pom.samples[i], steep.samples[i] + 1);
    if (steep.samples[i] == 1) continue;  // stopped at the top layer: nothing to interpolate
    ASSERT_GE(pom.depth[i], steep.depth[i] - 1.0f / 16.0f - 1e-6f);
    ASSERT_LE(pom.depth[i], steep.depth[i] + 1e-6f);
  }
}

TEST(Pom, OnAPlaneItIsExact) {
  // Linear interpolation between two layers is exact where the surface is linear.
  const DepthMap map = tilted_plane(64);
  const ExactIntersector exact(map, Wrap::clamp);
  const RayBatch rays = test::random_rays(300, 60.0, 9);
  const HitBuffers hits = trace_with(map, rays, params_for(Technique::pom, "8", Wrap::clamp));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const double u0 = rays.tx[i],
                 d = exact.intersect(u0, rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.1).t;
    if (hits.u[i] < 1.0 / 64.0 || hits.u[i] > 63.0 / 64.0) continue;  // the clamped border is not linear
    ASSERT_NEAR(hits.depth[i], d, 1e-4);
  }
}

TEST(Secant, WithoutIterationsItIsPom) {
  const DepthMap map = make_builtin_heightfield("bricks", 128, 2);
  const RayBatch rays = test::random_rays(1000, 80.0, 21);
  auto params = params_for(Technique::secant, "10");
  params.refine = 0;
  const HitBuffers secant = trace_with(map, rays, params);
  const HitBuffers pom = trace_with(map, rays, params_for(Technique::pom, "10"));
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(secant.u[i], pom.u[i]);
    ASSERT_EQ(secant.v[i], pom.v[i]);
    ASSERT_EQ(secant.depth[i], pom.depth[i]);
    ASSERT_EQ(secant.samples[i], pom.samples[i]);
  }
}

TEST(Secant, HitStaysBetweenItsLayersAndConvergesOnTheExactHit) {
  // Regula falsi keeps a bracket around the crossing: the hit never leaves the steep layer pair,
  // each iteration costs one sample, and on a smooth field more iterations never move it away.
  const DepthMap map = make_builtin_heightfield("waves", 128, 2);
  const ExactIntersector exact(map, Wrap::repeat);
  const RayBatch rays = test::random_rays(1000, 70.0, 22);
  const HitBuffers steep = trace_with(map, rays, params_for(Technique::steep, "16"));
  double error_sum[2] = {0.0, 0.0};
  for (int n = 0; n < 2; ++n) {
    auto params = params_for(Technique::secant, "16");
    params.refine = n == 0 ? 1 : 6;
    const HitBuffers hits = trace_with(map, rays, params);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(hits.samples[i], steep.samples[i] + 1 + std::uint32_t(params.refine_steps()));
      if (steep.samples[i] == 1) continue;
      ASSERT_GE(hits.depth[i], steep.depth[i] - 1.0f / 16.0f - 1e-6f);
      ASSERT_LE(hits.depth[i], steep.depth[i] + 1e-6f);
      const double d = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.1).t;
      error_sum[n] += std::fabs(hits.depth[i] - d);
    }
  }
  EXPECT_LT(error_sum[1], 0.5 * error_sum[0]);
}

TEST(Maxmip, EqualsTheExactReferenceUpToFloatRounding) {
  // Every builtin, both wraps, a power-of-two and an odd size (REPEAT's pyramid stops early, CLAMP
  // has edge cells), rays up to 88 degrees: the float walk finds the exact hit.
  for (const std::string& name : builtin_heightfield_names()) {
    for (int size : {64, 45}) {
      const DepthMap map = make_builtin_heightfield(name, size, 4);
      const RayBatch rays = test::random_rays(600, 88.0, std::hash<std::string>{}(name) + std::size_t(size));
      for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
        const HitBuffers hits = trace_with(map, rays, params_for(Technique::maxmip, "1", wrap));
        TechniqueParams exact_params;
        exact_params.wrap = wrap;
        const HitBuffers exact = exact_hits(map, rays, exact_params, LightVisibility::skip);
        std::vector<double> errors;
        for (std::size_t i = 0; i < rays.size(); ++i)
          if (!rays.is_padding(i))
            errors.push_back(uv_error_texels(hits.u[i], hits.v[i], exact.u[i], exact.v[i], size, size));
        std::sort(errors.begin(), errors.end());
        EXPECT_LE(errors[errors.size() * 99 / 100], 1e-3)
            << name << " " << size << (wrap == Wrap::repeat ? " repeat" : " clamp");
        EXPECT_LE(errors.back(), 0.05)
            << name << " " << size << (wrap == Wrap::repeat ? " repeat" : " clamp");
      }
    }
  }
}

TEST(Maxmip, StraightDownAndOnAOneTexelWideClampMap) {
  // Straight down the path is a point (both rates 0); a 1 x 8 CLAMP map has no interior cell.
  const DepthMap column{1, 8, {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f}};
  const HitBuffers down = trace_with(column, one_ray(0.5f, 0.5f, 0.0f, 0.0f, 1.0f),
                                     params_for(Technique::maxmip, "1", Wrap::clamp));
  EXPECT_NEAR(down.depth[0], sample_depth(column, Wrap::clamp, 0.5f, 0.5f), 1e-6);
  const HitBuffers slanted = trace_with(column, one_ray(0.5f, 0.3f, 0.3f, 0.5f, 0.8f),
                                        params_for(Technique::maxmip, "1", Wrap::clamp));
  const ExactIntersector exact(column, Wrap::clamp);
  EXPECT_NEAR(slanted.depth[0], exact.intersect(0.5, 0.3, 0.3, 0.5, 0.8, 0.1).t, 1e-5);
}

TEST(Cone, HandTracedOnAFlatDepth) {
  // D = 0.5 everywhere: nothing above any texel, every cone kMaxConeRatio = 4. Each step falls
  // 4 / (r + 4) of the gap (r = s |V.xy| / V.z = 0.075): gaps 0.5, 0.0092, 1.7e-4, 3.1e-6; the
  // fourth read finds the ray within 2^-16 above the surface and ends there, without halvings.
  const DepthMap map{8, 8, std::vector<float>(64, 0.5f)};
  const float vx = 0.6f, vy = 0.0f, vz = 0.8f;
  const HitBuffers hits = trace_with(map, one_ray(0.5f, 0.5f, vx, vy, vz), params_for(Technique::cone, "16"));
  EXPECT_EQ(hits.samples[0], 4u);
  EXPECT_GT(hits.depth[0], 0.5f - 1.52587890625e-5f);
  EXPECT_LE(hits.depth[0], 0.5f);
  EXPECT_EQ(hits.u[0], 0.5f - vx / vz * 0.1f * hits.depth[0]);
  // Straight down the first step lands on the surface: the second read finds it there.
  const HitBuffers down =
      trace_with(map, one_ray(0.5f, 0.5f, 0.0f, 0.0f, 1.0f), params_for(Technique::cone, "16"));
  EXPECT_EQ(down.samples[0], 2u);
  EXPECT_EQ(down.depth[0], 0.5f);
}

TEST(Cone, HalvingsStartFromABracketOfTheExactHitOnSmoothMaps) {
  // On a smooth field the relaxed cones let a ray cross the surface at most once per step, so
  // the bracket the halvings start from holds the exact hit: with enough halvings every ray that
  // ended its steps (by crossing the surface or coming within 2^-16 above it) ends on the exact
  // hit. Rays still stepping after N reads (crawling past a near-tangent slope) are rare.
  const DepthMap map = make_builtin_heightfield("waves", 128, 2);
  const RayBatch rays = test::random_rays(4000, 70.0, 31);
  for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
    const ExactIntersector exact(map, wrap);
    auto params = params_for(Technique::cone, "64", wrap);
    params.refine = 0;
    const HitBuffers reads = trace_with(map, rays, params);  // without halvings: the reads
    params.refine = 24;
    const HitBuffers hits = trace_with(map, rays, params);
    std::size_t still_stepping = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (reads.samples[i] == 64) {
        ++still_stepping;
        continue;
      }
      const double d = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.1).t;
      ASSERT_NEAR(hits.depth[i], d, 1e-3) << "ray " << i << (wrap == Wrap::repeat ? " repeat" : " clamp");
    }
    EXPECT_LE(still_stepping, rays.size() / 500);
  }
}

TEST(Cone, AtMostCeilNReadsAndRefineHalvings) {
  const DepthMap map = make_builtin_heightfield("bricks", 64, 2);
  const RayBatch rays = test::random_rays(2000, 85.0, 32);
  for (const char* layers : {"1", "3", "3-9"})
    for (int refine : {0, 2, 6}) {
      auto params = params_for(Technique::cone, layers);
      params.refine = refine;
      const HitBuffers hits = trace_with(map, rays, params);
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const LayerSpec spec = params.layers;
        const float a = std::fabs(rays.vz[i]);
        const float n = spec.min_layers == spec.max_layers
                            ? spec.min_layers
                            : spec.max_layers * (1.0f - a) + spec.min_layers * a;
        ASSERT_LE(hits.samples[i], std::uint32_t(std::ceil(n)) + std::uint32_t(refine))
            << layers << " refine " << refine;
        ASSERT_GE(hits.samples[i], 1u);
      }
    }
}

TEST(DynamicLayers, FollowTheTutorialsMix) {
  // N = mix(32, 8, |V.z|): straight down 8 layers, at V.z = 0.5 twenty.
  const DepthMap map{8, 8, std::vector<float>(64, 1.0f)};
  const HitBuffers down =
      trace_with(map, one_ray(0.5f, 0.5f, 0.0f, 0.0f, 1.0f), params_for(Technique::steep, "8-32"));
  EXPECT_EQ(down.samples[0], 9u);  // first read + 8 layers to reach depth 1
  const float s = std::sqrt(0.75f);
  const HitBuffers tilted =
      trace_with(map, one_ray(0.5f, 0.5f, s, 0.0f, 0.5f), params_for(Technique::steep, "8-32"));
  EXPECT_EQ(tilted.samples[0], 21u);
}

TEST(Bounds, ExtremeParametersStayFiniteAndBounded) {
  const DepthMap map = make_builtin_heightfield("spikes", 64, 1);
  const RayBatch rays = make_ray_list({0.3f, 0.7f, 0.5f}, {0.3f, 0.1f, 0.5f}, {0.7071f, 1.0f, 0.0f},
                                      {0.7071f, 0.0f, 0.0f}, {1e-6f, 1e-6f, 1.0f});
  for (Technique technique : test::all_technique_ids())
    for (const char* layers : {"1", "1-1", "256", "8-32"})
      for (float scale : {0.0f, 1.0f}) {
        auto params = params_for(technique, layers);
        params.scale = scale;
        const HitBuffers hits = trace_with(map, rays, params);
        const LayerSpec spec = parse_layer_spec(layers);
        for (std::size_t i = 0; i < rays.size(); ++i) {
          ASSERT_TRUE(std::isfinite(hits.u[i]) && std::isfinite(hits.v[i]) && std::isfinite(hits.depth[i]) &&
                      std::isfinite(hits.shadow[i]))
              << to_string(technique) << " " << layers << " scale " << scale;
          if (technique == Technique::maxmip) {
            // Not layered: its walk is bounded by the path's cells times the pyramid's levels,
            // at most five texel reads a pass (64 x 64: 7 levels; path of s |V.xy| / V.z W cells).
            const double cells = scale * 64.0 * (std::fabs(rays.vx[i]) + std::fabs(rays.vy[i])) / rays.vz[i];
            ASSERT_LE(hits.samples[i], 5.0 * 2.0 * (7 + 2) * (cells + 2.0) + 5.0);
            continue;
          }
          // steps + first read + refinement + POM/shadow extras
          ASSERT_LE(hits.samples[i], 2 * (std::ceil(spec.max_layers) + 3) + 5);
        }
      }
}

TEST(Shadow, LitFromStraightAboveOnAFlatMapIsLit) {
  const DepthMap map{8, 8, std::vector<float>(64, 0.5f)};
  auto params = params_for(Technique::shadow, "16");
  params.light[0] = 0.0f;
  params.light[1] = 0.0f;
  params.light[2] = 1.0f;
  const HitBuffers hits = trace_with(map, one_ray(0.5f, 0.5f, 0.3f, 0.0f, 0.9539392f), params);
  EXPECT_EQ(hits.shadow[0], 1.0f);
}

}  // namespace
}  // namespace heightmarch
