#include "glsl/gl_context.hpp"

#include <cstdlib>

#include "heightmarch/error.hpp"

namespace heightmarch {

std::vector<GlPath> built_gl_paths() {
  std::vector<GlPath> paths;
#ifdef HEIGHTMARCH_HAVE_OSMESA
  paths.push_back(GlPath::osmesa);
#endif
#ifdef HEIGHTMARCH_HAVE_EGL
  paths.push_back(GlPath::egl);
#endif
  return paths;
}

std::unique_ptr<GlContext> make_gl_context(const GlTarget& target, int threads) {
  const std::vector<GlPath> built = built_gl_paths();
  const GlPath path = target.path.value_or(built.front());
  std::string with;
  for (GlPath p : built) with += (with.empty() ? "" : " and ") + display_name(p);
  check(GlTarget{path, target.device});
  // 0 would mean "render on the calling thread", which is one thread too.
  setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  // Each fragment here is a ray of its own footprint, which trilinear filtering reads at its own
  // level of detail, as GL specifies. Mesa 22.3's llvmpipe takes textureLod's level per fragment
  // (measured: the same hits with and without this); later ones take it once per 2 x 2 quad, from
  // its first fragment, unless told otherwise (read once, as LP_NUM_THREADS).
  setenv("GALLIVM_PERF", "no_quad_lod", 1);
#ifdef HEIGHTMARCH_HAVE_OSMESA
  if (path == GlPath::osmesa) return make_osmesa_context();
#endif
#ifdef HEIGHTMARCH_HAVE_EGL
  if (path == GlPath::egl) return make_egl_context(target.device);
#endif
  throw InputError("--gl " + to_string(path) + ": this heightmarch's GLSL worker was built with " + with +
                   " alone (its library was not found when it was built)");
}

#ifndef HEIGHTMARCH_HAVE_EGL
std::vector<GlDevice> list_egl_devices() { return {}; }
#endif

}  // namespace heightmarch
