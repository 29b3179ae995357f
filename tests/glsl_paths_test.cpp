// The GL paths against each other (heightmarch/gl_target.hpp): OSMesa and EGL's software device
// are the same rasteriser, llvmpipe, so every technique's hits must be bit-identical through both,
// at 4, 32 and 8-32 layers on every builtin heightfield. Skips, saying so, where the worker was
// built with one path alone (tests/scripts/test_gl_paths.sh runs the GLSL tests through such a
// worker).
#include <gtest/gtest.h>

#include <cstring>

#include "heightmarch/glsl_runner.hpp"
#include "test_support.hpp"

namespace heightmarch {
namespace {

HitBuffers draw_hits(GlslRunner& runner, const DepthMap& map, const TechniqueParams& params,
                     const RayBatch& rays) {
  runner.prepare(map, params, rays);
  runner.draw();
  HitBuffers hits;
  bool samples_known = false;
  runner.read(hits, samples_known);
  EXPECT_TRUE(samples_known);
  return hits;
}

// The first ray whose outputs differ in any bit (a NaN or a -0 included), or -1.
template <class T>
long long first_bit_difference(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(T)) != 0) return (long long)i;
  return -1;
}

TEST(GlslPaths, OsmesaAndEglGiveBitIdenticalHits) {
  const std::vector<GlPath> built = gl_paths_built();
  if (built.size() < 2)
    GTEST_SKIP() << "this GLSL worker was built with " << display_name(built.front())
                 << " alone: there is no second path to hold it against";
  GlslRunner& osmesa = GlslRunner::instance(1, {GlPath::osmesa, ""});
  GlslRunner& egl = GlslRunner::instance(1, {GlPath::egl, "software"});
  EXPECT_TRUE(egl.renderer().software);
  EXPECT_EQ(egl.renderer().renderer, osmesa.renderer().renderer) << "the same llvmpipe through both paths";
  EXPECT_NE(egl.renderer().label(), osmesa.renderer().label()) << "named apart by their paths";
  const RayBatch rays = make_view_rays(default_view(96, 64));
  std::size_t compared = 0;
  for (const std::string& name : builtin_heightfield_names()) {
    const DepthMap map = make_builtin_heightfield(name, 128, 1);
    for (const TechniqueInfo& t : techniques())
      for (const char* layers : {"4", "32", "8-32"}) {
        SCOPED_TRACE(name + ", " + std::string(t.name) + " " + layers);
        TechniqueParams params;
        params.technique = t.id;
        params.layers = layers_for(t.id, parse_layer_spec(layers));
        const HitBuffers a = draw_hits(osmesa, map, params, rays), b = draw_hits(egl, map, params, rays);
        EXPECT_EQ(first_bit_difference(a.u, b.u), -1) << "u";
        EXPECT_EQ(first_bit_difference(a.v, b.v), -1) << "v";
        EXPECT_EQ(first_bit_difference(a.depth, b.depth), -1) << "depth";
        EXPECT_EQ(first_bit_difference(a.samples, b.samples), -1) << "samples";
        EXPECT_EQ(first_bit_difference(a.shadow, b.shadow), -1) << "shadow";
        EXPECT_EQ(first_bit_difference(a.discarded, b.discarded), -1) << "discarded";
        ++compared;
      }
  }
  EXPECT_EQ(compared, builtin_heightfield_names().size() * techniques().size() * 3);
}

}  // namespace
}  // namespace heightmarch
