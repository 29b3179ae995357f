// The exact intersection: closed forms, and an independent brute-force search over every
// builtin heightfield, both wrap modes, view angles up to 85 degrees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "heightmarch/exact.hpp"
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
  return (1 - fy) * ((1 - fx) * tap(i, j) + fx * tap(i + 1, j)) + fy * ((1 - fx) * tap(i, j + 1) + fx * tap(i + 1, j + 1));
}

// Fine stepping (1/64 texel along the path, at most 1/8192 in depth), then bisection.
double brute_force_depth(const DepthMap& map, Wrap wrap, double tx, double ty, double vx, double vy,
                         double vz, double scale) {
  const double kx = -scale * vx / vz * map.width, ky = -scale * vy / vz * map.height;
  auto g = [&](double d) { return d - brute_depth(map, wrap, tx * map.width - 0.5 + kx * d, ty * map.height - 0.5 + ky * d); };
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

TEST(Exact, AgreesWithBruteForceOnEveryBuiltin) {
  std::size_t rays_checked = 0;
  for (const std::string& name : builtin_heightfield_names()) {
    const DepthMap map = make_builtin_heightfield(name, 128, 7);
    for (Wrap wrap : {Wrap::repeat, Wrap::clamp}) {
      const ExactIntersector exact(map, wrap);
      const RayBatch rays = test::random_rays(160, 88.0, std::hash<std::string>{}(name) + int(wrap));
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (rays.is_padding(i)) continue;
        for (double scale : {0.1, 0.35}) {
          const double d = exact.intersect(rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale).t;
          const double reference =
              brute_force_depth(map, wrap, rays.tx[i], rays.ty[i], rays.vx[i], rays.vy[i], rays.vz[i], scale);
          ASSERT_NEAR(d, reference, 1e-6) << name << (wrap == Wrap::repeat ? " repeat" : " clamp") << " ray " << i
                                          << " scale " << scale;
          ++rays_checked;
        }
      }
    }
  }
  EXPECT_GE(rays_checked, 2000u);
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
  EXPECT_THROW(check_exact_path_lengths(map, make_ray_list({0.5f}, {0.5f}, {0.0f}, {0.0f}, {1.0f}), params), InputError);
}

}  // namespace
}  // namespace heightmarch
