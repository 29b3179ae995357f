// Procedural heightfields: deterministic for (resolution, seed), periodic so that REPEAT tiles
// them seamlessly (except ramp, a closed-form test), depth in [0, 1].
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include "heightmarch/error.hpp"
#include "heightmarch/heightfield.hpp"
#include "heightmarch/memory_budget.hpp"

namespace heightmarch {
namespace {

constexpr double kTau = 6.283185307179586;

// splitmix64: our own generator, so builtins never depend on a standard library's distributions.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed * 0x9e3779b97f4a7c15ull + 0x632be59bd9b4e019ull) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  int below(int n) { return int(next() % std::uint64_t(n)); }

 private:
  std::uint64_t state_;
};

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Hash of an integer lattice point, wrapped with the period, in [0, 1).
double lattice(int i, int j, int period, std::uint64_t seed) {
  i = ((i % period) + period) % period;
  j = ((j % period) + period) % period;
  std::uint64_t h =
      seed ^ (std::uint64_t(i) * 0x9e3779b97f4a7c15ull) ^ (std::uint64_t(j) * 0xc2b2ae3d27d4eb4full);
  h = (h ^ (h >> 31)) * 0xbf58476d1ce4e5b9ull;
  h = (h ^ (h >> 29)) * 0x94d049bb133111ebull;
  return double((h ^ (h >> 32)) >> 11) * 0x1.0p-53;
}

// Periodic value noise with a smooth (quintic) blend; period cells across [0,1).
double value_noise(double u, double v, int period, std::uint64_t seed) {
  const double x = u * period, y = v * period;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  const double fx = x - i, fy = y - j;
  auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const double sx = fade(fx), sy = fade(fy);
  const double a = lattice(i, j, period, seed), b = lattice(i + 1, j, period, seed);
  const double c = lattice(i, j + 1, period, seed), d = lattice(i + 1, j + 1, period, seed);
  return (a + (b - a) * sx) * (1 - sy) + (c + (d - c) * sx) * sy;
}

using DepthFunction = std::function<double(double u, double v)>;

DepthMap sample_function(int res, const DepthFunction& depth) {
  DepthMap map{res, res, std::vector<float>(std::size_t(res) * std::size_t(res))};
  for (int j = 0; j < res; ++j)
    for (int i = 0; i < res; ++i)
      map.texels[std::size_t(j) * res + i] =
          float(std::clamp(depth((i + 0.5) / res, (j + 0.5) / res), 0.0, 1.0));
  return map;
}

// Rescales to span [lo, hi] exactly (a constant map stays at lo).
void normalize(DepthMap& map, float lo, float hi) {
  const auto [mn, mx] = std::minmax_element(map.texels.begin(), map.texels.end());
  const float a = *mn, range = *mx - *mn;
  for (float& d : map.texels) d = range > 0 ? lo + (hi - lo) * (d - a) / range : lo;
}

DepthMap waves(int res, std::uint64_t seed) {
  Random rng(seed);
  struct Wave {
    int fx, fy;
    double phase, amplitude;
  };
  std::vector<Wave> list;
  for (int k = 0; k < 4; ++k)
    list.push_back({1 + rng.below(4), rng.below(5) - 2, rng.uniform() * kTau, 0.5 / (k + 1)});
  DepthMap map = sample_function(res, [&](double u, double v) {
    double h = 0;
    for (const Wave& w : list) h += w.amplitude * std::sin(kTau * (w.fx * u + w.fy * v) + w.phase);
    return h;
  });
  normalize(map, 0.05f, 0.95f);
  return map;
}

DepthMap terrain(int res, std::uint64_t seed) {
  DepthMap map = sample_function(res, [&](double u, double v) {
    double h = 0, amplitude = 1;
    for (int octave = 0; octave < 6; ++octave) {
      h += amplitude * value_noise(u, v, 4 << octave, seed + std::uint64_t(octave) * 1013);
      amplitude *= 0.5;
    }
    return h;
  });
  normalize(map, 0.0f, 1.0f);
  return map;
}

// LearnOpenGL's bricks: shallow faces with a slight tilt per brick, deep mortar grooves, bevels.
DepthMap bricks(int res, std::uint64_t seed) {
  constexpr int kRows = 8, kPerRow = 4;
  constexpr double kMortar = 0.018, kBevel = 0.02;  // in uv: half-widths of groove and bevel
  return sample_function(res, [&](double u, double v) {
    const int row = int(std::floor(v * kRows));
    const double shift = (row % 2) ? 0.5 / kPerRow : 0.0;
    const double x = u + shift;
    const int column = int(std::floor(x * kPerRow));
    const double bx = x * kPerRow - column, by = v * kRows - row;
    // Distance to the brick's edge in uv.
    const double edge = std::min({bx / kPerRow, (1 - bx) / kPerRow, by / kRows, (1 - by) / kRows});
    const int brick = row * kPerRow + ((column % kPerRow) + kPerRow) % kPerRow;
    const double base = 0.05 + 0.08 * lattice(brick, 7, 1 << 20, seed);
    const double tilt = 0.04 * (lattice(brick, 11, 1 << 20, seed) - 0.5) * (bx - 0.5);
    const double face = base + tilt + 0.02 * value_noise(u, v, 32, seed + 5);
    const double groove = 0.9;
    return groove + (face - groove) * smoothstep(kMortar, kMortar + kBevel, edge);
  });
}

// LearnOpenGL's toy box: a raised frame and square wells with vertical walls and flat floors.
DepthMap toybox(int res, std::uint64_t seed) {
  constexpr int kCells = 4;
  return sample_function(res, [&](double u, double v) {
    const int ci = int(std::floor(u * kCells)), cj = int(std::floor(v * kCells));
    const double cx = u * kCells - ci, cy = v * kCells - cj;
    const double border = std::min({cx, 1 - cx, cy, 1 - cy});
    if (border < 0.12) return 0.0;  // the frame, at the top plane
    const double floor_depth = 0.35 + 0.6 * lattice(ci, cj, kCells, seed);
    // A step inside each well: an inner square at half the depth.
    return border > 0.3 ? 0.5 * floor_depth : floor_depth;
  });
}

// Thin deep pits a few texels wide scattered on a shallow base.
DepthMap spikes(int res, std::uint64_t seed) {
  DepthMap map =
      sample_function(res, [&](double u, double v) { return 0.1 + 0.05 * value_noise(u, v, 8, seed); });
  Random rng(seed + 99);
  const int pits = std::max(1, res * res / 1024);
  const int radius = std::max(1, res / 256);  // 2-4 texels wide at 512
  for (int p = 0; p < pits; ++p) {
    const int ci = rng.below(res), cj = rng.below(res);
    const float depth = float(0.7 + 0.3 * rng.uniform());
    for (int dj = -radius; dj < radius; ++dj)
      for (int di = -radius; di < radius; ++di) {
        const int i = ((ci + di) % res + res) % res, j = ((cj + dj) % res + res) % res;
        float& d = map.texels[std::size_t(j) * res + i];
        d = std::max(d, depth);
      }
  }
  return map;
}

// flat sits at half depth, so a flat map still shows a parallax shift.
DepthMap flat(int res, std::uint64_t) {
  return DepthMap{res, res, std::vector<float>(std::size_t(res) * res, 0.5f)};
}
DepthMap ramp(int res, std::uint64_t) {
  return sample_function(res, [](double u, double) { return u; });
}

}  // namespace

// The builtins: one row each, and the only list of them (docs/conventions.md describes each).
const std::vector<BuiltinHeightfield>& builtin_heightfields() {
  static const std::vector<BuiltinHeightfield> rows = {
      {"flat", flat, BuiltinHeightfield::test_only},
      {"ramp", ramp, BuiltinHeightfield::test_only},
      {"bricks", bricks, BuiltinHeightfield::in_quick_suite},  // first: the suite's gallery shows it
      {"toybox", toybox, BuiltinHeightfield::in_suite},
      {"terrain", terrain, BuiltinHeightfield::in_quick_suite},
      {"waves", waves, BuiltinHeightfield::in_suite},
      {"spikes", spikes, BuiltinHeightfield::in_suite},
  };
  return rows;
}

std::vector<std::string> builtin_heightfield_names() {
  std::vector<std::string> names;
  for (const BuiltinHeightfield& b : builtin_heightfields()) names.push_back(b.name);
  return names;
}

DepthMap make_builtin_heightfield(const std::string& name, int resolution, std::uint64_t seed) {
  if (resolution < 1 || resolution > kMaxDepthMapSide)
    throw InputError("builtin:" + name + ": resolution " + std::to_string(resolution) + " out of range [1, " +
                     std::to_string(kMaxDepthMapSide) + "]");
  check_memory_budget(kBytesPerDepthTexel * resolution * resolution,
                      "builtin:" + name + " at " + std::to_string(resolution));
  for (const BuiltinHeightfield& b : builtin_heightfields())
    if (name == b.name) return b.make(resolution, seed);
  std::string names;
  for (const auto& n : builtin_heightfield_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError("builtin:" + name + ": unknown builtin heightfield (" + names + ")");
}

}  // namespace heightmarch
