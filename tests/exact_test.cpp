// The exact intersection: closed forms, and an independent brute-force search over every
// builtin heightfield, both wrap modes, view angles up to 85 degrees.
#include "heightmarch/exact.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "heightmarch/mip_chain.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

// The bilinear surface written again, independently of the library, in double.
double brute_depth(const DepthMap& map, Wrap wrap, double x, double y) {
  auto tap = [&](long long i, long long j) {
    if (wrap == Wrap::repeat) {
      i = ((i % map.width) + map.width) % map.width;
      j = ((j % map.height) + map.height) % map.height;
    } else {
      i = std::clamp<long long>(i, 0, map.width - 1);
      j = std::clamp<long long>(j, 0, map.height - 1);
    }
    return double(map.at(int(i), int(j)));
  };
  const double fx = x - std::floor(x), fy = y - std::floor(y);
  const long long i = (long long)std::floor(x), j = (long long)std::floor(y);
  return (1 - fy) * ((1 - fx) * tap(i, j) + fx * tap(i + 1, j)) +
         fy * ((1 - fx) * tap(i, j + 1) + fx * tap(i + 1, j + 1));
}

// The first depth at or below a surface depth(u, v) along the ray, by fine stepping (1/64 of a
// texel of a W x H grid along the path, at most 1/8192 in depth), then bisection.
template <class Surface>
double brute_force_depth(const Surface& depth, int width, int height, double tx, double ty, double vx,
                         double vy, double vz, double scale) {
  const double ku = -scale * vx / vz, kv = -scale * vy / vz;
  auto g = [&](double d) { return d - depth(tx + ku * d, ty + kv * d); };
  if (g(0.0) >= 0.0) return 0.0;
  const double step =
      std::min(1.0 / 8192.0, 1.0 / 64.0 / std::max(1e-9, std::fabs(ku) * width + std::fabs(kv) * height));
  double lo = 0.0;
  for (double hi = step;; hi += step) {
    hi = std::min(hi, 1.0);
    if (g(hi) >= 0.0) {
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (g(mid) >= 0.0 ? hi : lo) = mid;
      }
      return hi;
    }
    if (hi >= 1.0) return 1.0;
    lo = hi;
  }
}

// The same on the level-0 bilinear surface.
double brute_force_depth(const DepthMap& map, Wrap wrap, double tx, double ty, double vx, double vy,
                         double vz, double scale) {
  const auto level0 = [&](double u, double v) {
    return brute_depth(map, wrap, u * map.width - 0.5, v * map.height - 0.5);
  };
  return brute_force_depth(level0, map.width, map.height, tx, ty, vx, vy, vz, scale);
}

TEST(Exact, FlatIsItsDepth) {
  const DepthMap map{4, 4, std::vector<float>(16, 0.375f)};
  for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
    const ExactIntersector exact(map, wrap);
    EXPECT_NEAR(exact.intersect(0.3, 0.7, 0.6, 0.0, 0.8, 0.1).t, 0.375, 1e-12);
    EXPECT_NEAR(exact.intersect(0.3, 0.7, -0.3, 0.5, std::sqrt(1 - 0.34), 1.0).t, 0.375, 1e-12);
  }
}

TEST(Exact, RampSolvedByHand) {
  // D = (i + 0.5) / 8 at texel i: bilinear in x = u W - 0.5 gives D(u) = u on [1/16, 15/16] (CLAMP).
  DepthMap map{8, 1, {}};
  for (int i = 0; i < 8; ++i) map.texels.push_back((i + 0.5f) / 8.0f);
  const ExactIntersector exact(map, Wrap::clamp);
  // Ray entering at u = 0.8 towards -u: point at depth d is u = 0.8 - d s vx / vz; d = u gives
  // d = 0.8 / (1 + s vx / vz).
  const double vx = 0.6, vz = 0.8, s = 0.5;
  EXPECT_NEAR(exact.intersect(0.8, 0.5, vx, 0.0, vz, s).t, 0.8 / (1 + s * vx / vz), 1e-12);
}

// The double walk from depth 0 and the reference as exact_hits computes it (float pass, then
// the double walk), both against the brute-force search.
TEST(Exact, AgreesWithBruteForceOnEveryBuiltin) {
  std::size_t rays_checked = 0;
  for (const std::string& name : builtin_heightfield_names()) {
    const DepthMap map = make_builtin_heightfield(name, 128, 7);
    for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
      const ExactIntersector exact(map, wrap);
      const RayBatch rays = test::random_rays(160, 88.0, std::hash<std::string>{}(name) + int(wrap));
      for (float scale : {0.1f, 0.35f}) {
        TechniqueParams params;
        params.scale = scale;
        params.wrap = wrap;
        const HitBuffers hits = exact_hits(map, rays, params, LightVisibility::skip);
        for (std::size_t i = 0; i < rays.size(); ++i) {
          if (rays.is_padding(i)) continue;
          const double d =
              exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale).t;
          const double reference =
              brute_force_depth(map, wrap, rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale);
          ASSERT_NEAR(d, reference, 1e-6)
              << name << (wrap == Wrap::repeat ? " repeat" : " clamp") << " ray " << i << " scale " << scale;
          ASSERT_NEAR(hits.depth[i], reference, 1e-6)
              << name << (wrap == Wrap::repeat ? " repeat" : " clamp") << " ray " << i << " scale " << scale
              << " (exact_hits)";
          ++rays_checked;
        }
      }
    }
  }
  EXPECT_GE(rays_checked, 2000u);
}

// exact_hits (the float pass at each ISA, then the double walk from where it stopped) against
// the double walk alone from depth 0: every builtin, power-of-two and odd sides, both wraps,
// rays to 88 degrees entering anywhere (T a little outside [0, 1]^2 too), scales to 1; the
// light's visibility too. The hits are the same at every ISA, bit for bit.
TEST(Exact, FloatPassThenDoubleAgreesWithTheDoubleWalk) {
  std::size_t rays_checked = 0;
  for (const std::string& name : builtin_heightfield_names())
    for (int side : {45, 64, 128}) {
      const DepthMap map = make_builtin_heightfield(name, side, 5);
      for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
        const ExactIntersector exact(map, wrap);
        test::Random rng(std::hash<std::string>{}(name) + std::uint64_t(side) * 7 + std::uint64_t(wrap));
        std::vector<float> tx, ty, vx, vy, vz;
        for (int i = 0; i < 300; ++i) {
          const double theta = rng.uniform(0.0, 88.0) * M_PI / 180.0, phi = rng.uniform(0.0, 2.0 * M_PI);
          tx.push_back(float(rng.uniform(-0.1, 1.1)));
          ty.push_back(float(rng.uniform(-0.1, 1.1)));
          vx.push_back(float(std::sin(theta) * std::cos(phi)));
          vy.push_back(float(std::sin(theta) * std::sin(phi)));
          vz.push_back(float(std::cos(theta)));
        }
        const RayBatch rays = make_ray_list(tx, ty, vx, vy, vz);
        for (float scale : {0.1f, 0.35f, 1.0f}) {
          TechniqueParams params;
          params.scale = scale;
          params.wrap = wrap;
          const HitBuffers hits = exact_hits(map, rays, params, LightVisibility::skip, Isa::scalar);
          for (std::size_t i = 0; i < rays.size(); ++i) {
            if (rays.is_padding(i)) continue;
            const double d =
                exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale).t;
            ASSERT_NEAR(hits.depth[i], d, 1e-6)
                << name << " " << side << (wrap == Wrap::repeat ? " repeat" : " clamp") << " ray " << i
                << " scale " << scale;
            ++rays_checked;
          }
          // With the light walked too (the shadow's reference), from the hit in double.
          const HitBuffers lit = exact_hits(map, rays, params, LightVisibility::compute);
          for (std::size_t i = 0; i < rays.size(); ++i) {
            if (rays.is_padding(i)) continue;
            const double d =
                exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale).t;
            const double u = rays.tx[i] - d * (double(scale) / rays.vz[i]) * rays.vx[i];
            const double v = rays.ty[i] - d * (double(scale) / rays.vz[i]) * rays.vy[i];
            ASSERT_NEAR(lit.depth[i], d, 1e-6) << name << " " << side << " ray " << i << " (light walked)";
            ASSERT_EQ(lit.shadow[i], exact.visible(u, v, d, params.light, scale) ? 1.0f : 0.0f)
                << name << " " << side << " ray " << i;
          }
          for (Isa isa : supported_isas()) {
            const HitBuffers at_isa = exact_hits(map, rays, params, LightVisibility::skip, isa);
            EXPECT_TRUE(at_isa.depth == hits.depth && at_isa.u == hits.u && at_isa.v == hits.v &&
                        at_isa.samples == hits.samples)
                << name << " " << side << " at " << to_string(isa);
          }
        }
      }
    }
  EXPECT_GE(rays_checked, 30000u);
}

// The case the float pass's margin is for: a ray that dips into a lone shallow texel's peak by a
// few 1e-7 in depth, less than what float rounding moves the walk's path by on a 512 x 512 map.
// Without the margin (eta = 0 in maxmip_exact_bound) about a fifth of these rays went on to the
// floor at depth 1; with it the answer is the double walk's.
TEST(Exact, FloatPassStopsBeforeAGrazedPeak) {
  constexpr int kSide = 512;
  test::Random rng(11);
  std::size_t rays_checked = 0, peaks_hit = 0;
  for (Wrap wrap : {Wrap::repeat, Wrap::clamp})
    for (int k = 0; k < 100; ++k) {
      const double theta = rng.uniform(30.0, 88.0) * M_PI / 180.0, phi = rng.uniform(0.0, 2.0 * M_PI);
      const RayBatch rays = make_ray_list({float(rng.uniform(0.2, 0.8))}, {float(rng.uniform(0.2, 0.8))},
                                          {float(std::sin(theta) * std::cos(phi))},
                                          {float(std::sin(theta) * std::sin(phi))}, {float(std::cos(theta))});
      TechniqueParams params;
      params.wrap = wrap;
      const double s = params.scale, vz = rays.vz[0];
      const double x0 = rays.tx[0] * double(kSide) - 0.5, y0 = rays.ty[0] * double(kSide) - 0.5;
      const double dx = -s * rays.vx[0] / vz * kSide, dy = -s * rays.vy[0] / vz * kSide;
      // The peak: the texel nearest the path at depth t_peak, everything else at depth 1.
      const double t_peak = rng.uniform(0.2, 0.8);
      const double pi = std::round(x0 + dx * t_peak), pj = std::round(y0 + dy * t_peak);
      if (pi < 2.0 || pj < 2.0 || pi > kSide - 3.0 || pj > kSide - 3.0) continue;  // off the map
      // How far the path dips below a peak of depth a (the surface is 1 - (1 - a) tent tent).
      auto dip = [&](double a) {
        double best = -1.0, t_best = t_peak, span = 2.0 / (std::fabs(dx) + std::fabs(dy));
        for (int round = 0; round < 3; ++round, span /= 500.0) {
          const double lo = t_best - span, hi = t_best + span;
          for (int q = 0; q <= 1000; ++q) {
            const double t = lo + (hi - lo) * q / 1000.0;
            const double wx = std::max(0.0, 1.0 - std::fabs(x0 + dx * t - pi));
            const double wy = std::max(0.0, 1.0 - std::fabs(y0 + dy * t - pj));
            if (const double g = t - (1.0 - (1.0 - a) * wx * wy); g > best) best = g, t_best = t;
          }
        }
        return best;
      };
      constexpr double kDip = 3e-7;
      double lo = -1.0, hi = t_peak;  // the dip shrinks as the peak deepens
      for (int it = 0; it < 40; ++it) (dip(0.5 * (lo + hi)) > kDip ? lo : hi) = 0.5 * (lo + hi);
      const float a = float(0.5 * (lo + hi));
      if (a < 0.0f || dip(a) < 0.5 * kDip || dip(a) > 2.0 * kDip) continue;  // no such peak in [0, 1]
      DepthMap map{kSide, kSide, std::vector<float>(std::size_t(kSide) * kSide, 1.0f)};
      map.texels[std::size_t(pj) * kSide + std::size_t(pi)] = a;
      const double d =
          ExactIntersector(map, wrap).intersect(rays.tx[0], rays.ty[0], rays.vx[0], rays.vy[0], vz, s).t;
      const HitBuffers hits = exact_hits(map, rays, params, LightVisibility::skip);
      ASSERT_NEAR(hits.depth[0], d, 1e-6) << (wrap == Wrap::repeat ? "repeat" : "clamp") << " ray " << k;
      ++rays_checked;
      peaks_hit += d < 0.99;
    }
  EXPECT_GE(rays_checked, 80u);
  EXPECT_GE(peaks_hit, rays_checked * 9 / 10) << "the construction makes rays that graze their peak";
}

TEST(Exact, VisibilityOfAPitFloor) {
  // A 1-texel-wide deep pit in a shallow plane: from its floor, a light at a grazing angle is
  // hidden by the pit's wall, a light straight above is visible.
  DepthMap map{16, 16, std::vector<float>(256, 0.0f)};
  for (int j = 0; j < 16; ++j) map.texels[j * 16 + 8] = 1.0f;
  const ExactIntersector exact(map, Wrap::repeat);
  const float above[3] = {0.0f, 0.0f, 1.0f};
  const float grazing[3] = {0.9805807f, 0.0f, 0.1961161f};
  const double u = 8.5 / 16.0, v = 0.5, d = 1.0;
  EXPECT_TRUE(exact.visible(u, v, d, above, 0.5));
  EXPECT_FALSE(exact.visible(u, v, d, grazing, 0.5));
}

}  // namespace
}  // namespace heightmarch

namespace heightmarch {
namespace {

TEST(Exact, GrazingPathsAreRefusedPastTheLimit) {
  const DepthMap map = make_builtin_heightfield("bricks", 512, 1);
  TechniqueParams params;
  params.scale = 1.0f;
  // The ray of a 115-second walk before the limit: V.z = 6e-7 at scale 1 crosses 8.5e8 cells.
  const RayBatch grazing = make_ray_list({0.5f}, {0.5f}, {1.0f}, {0.0f}, {6e-7f});
  EXPECT_THROW(check_exact_path_lengths(map, grazing, params), InputError);
  EXPECT_THROW(exact_hits(map, grazing, params, LightVisibility::skip), InputError);
  // Just inside the limit it is solved, and its padding copies are not walked again.
  const float vz = float(1.05 * (512 + 512) / kMaxExactPathCells);
  const RayBatch inside = make_ray_list({0.5f}, {0.5f}, {1.0f}, {0.0f}, {vz});
  EXPECT_NO_THROW(check_exact_path_lengths(map, inside, params));
  const HitBuffers hits = exact_hits(map, inside, params, LightVisibility::compute);
  EXPECT_GT(hits.depth[0], 0.0f);
  for (std::size_t i = 1; i < inside.size(); ++i) EXPECT_EQ(hits.samples[i], 0u);
  // A light that grazes is refused the same way.
  params.light[0] = 1.0f;
  params.light[1] = 0.0f;
  params.light[2] = 1e-5f;
  EXPECT_THROW(check_exact_path_lengths(map, make_ray_list({0.5f}, {0.5f}, {0.0f}, {0.0f}, {1.0f}), params),
               InputError);
}

}  // namespace
}  // namespace heightmarch

// The exact hit on the surface a ray reads (FilteredExactReference): level 0 where it reads
// level 0, a hand-solved blend of two levels, and the blend against a brute-force march on it.
namespace heightmarch {
namespace {

// A ray batch with one footprint for every ray: gradients (du_dx, dv_dx, du_dy, dv_dy).
RayBatch with_footprint(RayBatch rays, float du_dx, float dv_dx, float du_dy, float dv_dy) {
  rays.du_dx.assign(rays.size(), du_dx);
  rays.dv_dx.assign(rays.size(), dv_dx);
  rays.du_dy.assign(rays.size(), du_dy);
  rays.dv_dy.assign(rays.size(), dv_dy);
  return rays;
}

// A ray that reads level 0 (a level of detail of 0, bilinear filtering, a technique that reads
// texels) gets today's exact reference's hit, bit for bit: on every builtin, a perspective view
// whose near rows magnify the map (level 0) and whose far rows minify it.
TEST(FilteredExact, ReadsOfLevelZeroAreTheExactReferenceBitForBit) {
  for (const std::string& name : builtin_heightfield_names()) {
    const DepthMap map = make_builtin_heightfield(name, 128, 3);
    const RayBatch rays = make_view_rays(default_view(192, 192));
    const int last = mip_level_count(map.width, map.height) - 1;
    for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
      TechniqueParams params;
      params.wrap = wrap;
      params.filter = Filter::trilinear;
      const HitBuffers level0 = exact_hits(map, rays, params, LightVisibility::skip);
      HitBuffers read;
      FilteredExactReference(map, params).run(rays, level0, read);
      const ExactIntersector intersector(map, wrap);
      const FilteredExactReference reference(map, params);
      std::size_t at_level0 = 0, above = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (rays.is_padding(i)) continue;
        const float lod = level_of_detail(rays.du_dx[i], rays.dv_dx[i], rays.du_dy[i], rays.dv_dy[i],
                                          float(map.width), float(map.height), last);
        if (lod > 0.0f) {
          ++above;
          continue;
        }
        ++at_level0;
        ASSERT_TRUE(read.u[i] == level0.u[i] && read.v[i] == level0.v[i] &&
                    read.depth[i] == level0.depth[i] && read.samples[i] == level0.samples[i])
            << name << " ray " << i;
        // And a ray's level 0 in the reference's own chain is the map's double walk, bit for bit.
        ASSERT_EQ(
            reference.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], 0.0f).t,
            intersector.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], params.scale).t)
            << name << " ray " << i;
      }
      EXPECT_GT(at_level0, rays.ray_count / 10) << name;
      EXPECT_GT(above, rays.ray_count / 10) << name;
      // Under bilinear, and for maxmip (which reads texels) under trilinear, every ray reads level 0.
      for (const auto& [technique, filter] :
           {std::pair{Technique::pom, Filter::bilinear}, std::pair{Technique::maxmip, Filter::trilinear}}) {
        TechniqueParams level0_read = params;
        level0_read.technique = technique;
        level0_read.filter = filter;
        HitBuffers same;
        FilteredExactReference(map, level0_read).run(rays, level0, same);
        EXPECT_TRUE(same.u == level0.u && same.v == level0.v && same.depth == level0.depth) << name;
      }
    }
  }
}

// A map of 2 x 2 texels, whose chain is two levels: 0.25 in column 0 and 0.75 in column 1, its
// level 1 their mean 0.5 (CLAMP). Between the texel centres u = 1/4 and 3/4 level 0 is u, so at
// level of detail 1/2 the surface is (1 - f) u + 0.5 f; a ray entering at u = 1/2 at 45 degrees,
// travelling towards -u, at scale 1/2 is at u = 1/2 - d / 2 at depth d, which meets it at
// d = 0.5 / (1 + 0.5 (1 - f)) = 0.4 (level 0 alone: 1/3).
TEST(FilteredExact, HandSolvedOnATwoLevelChain) {
  const DepthMap map{2, 2, {0.25f, 0.75f, 0.25f, 0.75f}};
  ASSERT_EQ(build_mip_chain(map).size(), 2u);
  TechniqueParams params;
  params.wrap = Wrap::clamp;
  params.filter = Filter::trilinear;
  params.scale = 0.5f;
  const float c = float(std::sqrt(0.5));
  // rho = |(du/dx W, dv/dx H)| = sqrt(2): level of detail 1/2, exactly.
  const RayBatch rays =
      with_footprint(make_ray_list({0.5f}, {0.5f}, {c}, {0.0f}, {c}), 0.5f, 0.5f, 0.0f, 0.0f);
  ASSERT_EQ(level_of_detail(rays.du_dx[0], rays.dv_dx[0], rays.du_dy[0], rays.dv_dy[0], 2.0f, 2.0f, 1), 0.5f);
  const FilteredExactReference reference(map, params);
  EXPECT_NEAR(reference.intersect(0.5, 0.5, c, 0.0, c, 0.5f).t, 0.4, 1e-12);
  const HitBuffers level0 = exact_hits(map, rays, params, LightVisibility::skip);
  HitBuffers read;
  reference.run(rays, level0, read);
  EXPECT_NEAR(read.depth[0], 0.4, 1e-7);
  EXPECT_NEAR(read.u[0], 0.3, 1e-7);
  EXPECT_NEAR(level0.depth[0], 1.0 / 3.0, 1e-7);
}

// Both levels varying, the hit past a side of level 1's cells inside a cell of level 0: texels
// 0, 0.5, 0.25, 0.75 along u (CLAMP), level 1 0.25 and 0.5. At f = 1/2 the surface is
// -0.4375 + 1.25 u on [0.625, 0.75] and -0.25 + u on [0.75, 0.875] (where level 1 is clamped flat);
// a ray entering at u = 0.85 at 45 degrees, travelling towards -u, at scale 1/2 stays above it to
// u = 0.75 (d = 0.2) and meets it at d = 0.625 / 1.625 = 5/13.
TEST(FilteredExact, HandSolvedAcrossTheCoarserLevelsCells) {
  DepthMap map{4, 4, {}};
  for (int j = 0; j < 4; ++j)
    for (float t : {0.0f, 0.5f, 0.25f, 0.75f}) map.texels.push_back(t);
  TechniqueParams params;
  params.wrap = Wrap::clamp;
  params.filter = Filter::trilinear;
  params.scale = 0.5f;
  const double c = std::sqrt(0.5);
  const FilteredExactReference reference(map, params);
  EXPECT_NEAR(reference.intersect(0.85, 0.5, c, 0.0, c, 0.5f).t, 5.0 / 13.0, 1e-12);
}

// The blend against a brute-force march on it (written apart from the library, from the chain's
// levels): every builtin, both wraps, power-of-two and odd sides, levels of detail over the whole
// chain (whole ones too), rays to 85 degrees. The hits agree to 1e-4 texel of level 0.
TEST(FilteredExact, AgreesWithABruteForceMarchOnTheBlend) {
  std::size_t rays_checked = 0;
  double worst = 0;
  for (const std::string& name : builtin_heightfield_names())
    for (int side : {45, 64}) {
      const DepthMap map = make_builtin_heightfield(name, side, 9);
      const std::vector<DepthMap> chain = build_mip_chain(map);
      const int last = int(chain.size()) - 1;
      for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
        TechniqueParams params;
        params.wrap = wrap;
        params.filter = Filter::trilinear;
        params.scale = 0.2f;
        const FilteredExactReference reference(map, params);
        test::Random rng(std::hash<std::string>{}(name) + std::uint64_t(side) * 3 + std::uint64_t(wrap));
        for (int k = 0; k < 40; ++k) {
          const double theta = rng.uniform(0.0, 85.0) * M_PI / 180.0, phi = rng.uniform(0.0, 2.0 * M_PI);
          const double tx = rng.uniform(-0.1, 1.1), ty = rng.uniform(-0.1, 1.1);
          const double vx = std::sin(theta) * std::cos(phi), vy = std::sin(theta) * std::sin(phi),
                       vz = std::cos(theta);
          const float lod = k % 8 == 0 ? float(rng.next() % std::uint64_t(last + 1))
                                       : float(rng.uniform(0.0, double(last)));
          const int a = int(std::floor(lod)), b = std::min(a + 1, last);
          const double f = double(lod) - a;
          const auto blend = [&](double u, double v) {
            const double da =
                brute_depth(chain[a], wrap, u * chain[a].width - 0.5, v * chain[a].height - 0.5);
            const double db =
                brute_depth(chain[b], wrap, u * chain[b].width - 0.5, v * chain[b].height - 0.5);
            return da + f * (db - da);
          };
          const double expected =
              brute_force_depth(blend, map.width, map.height, tx, ty, vx, vy, vz, params.scale);
          const double d = reference.intersect(tx, ty, vx, vy, vz, lod).t;
          // The hits' distance in texels of level 0.
          const double texels =
              std::fabs(d - expected) * params.scale / vz * std::hypot(vx * map.width, vy * map.height);
          worst = std::max(worst, texels);
          ASSERT_LE(texels, 1e-4) << name << " " << side << (wrap == Wrap::repeat ? " repeat" : " clamp")
                                  << " ray " << k << " lod " << lod << ": " << d << " vs " << expected;
          ++rays_checked;
        }
      }
    }
  EXPECT_GE(rays_checked, 500u);
  std::printf("blend vs brute force: %zu rays, worst %.3g texel\n", rays_checked, worst);
}

}  // namespace
}  // namespace heightmarch
