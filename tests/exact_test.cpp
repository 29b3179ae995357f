// The exact intersection: closed forms, and an independent brute-force search over every
// builtin heightfield, both wrap modes, view angles up to 85 degrees.
#include "heightmarch/exact.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

// Fine stepping (1/64 texel along the path, at most 1/8192 in depth), then bisection.
double brute_force_depth(const DepthMap& map, Wrap wrap, double tx, double ty, double vx, double vy,
                         double vz, double scale) {
  const double kx = -scale * vx / vz * map.width, ky = -scale * vy / vz * map.height;
  auto g = [&](double d) {
    return d - brute_depth(map, wrap, tx * map.width - 0.5 + kx * d, ty * map.height - 0.5 + ky * d);
  };
  if (g(0.0) >= 0.0) return 0.0;
  const double step = std::min(1.0 / 8192.0, 1.0 / 64.0 / std::max(1e-9, std::fabs(kx) + std::fabs(ky)));
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
