#include "glsl/gl_context.hpp"

#include <cstdlib>

#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

// The registered paths; a function's static, so that registering from another file's static
// initialiser finds it made.
std::vector<GlPathContexts>& registered() {
  static std::vector<GlPathContexts> paths;
  return paths;
}

const GlPathContexts* registered(GlPath path) {
  for (const GlPathContexts& p : registered())
    if (p.path == path) return &p;
  return nullptr;
}

}  // namespace

bool register_gl_path(const GlPathContexts& contexts) {
  registered().push_back(contexts);
  return true;
}

std::vector<GlPath> built_gl_paths() {
  std::vector<GlPath> paths;
#define HEIGHTMARCH_GL_PATH_BUILT(id, ...) \
  if (registered(GlPath::id)) paths.push_back(GlPath::id);
  HEIGHTMARCH_GL_PATHS(HEIGHTMARCH_GL_PATH_BUILT)
#undef HEIGHTMARCH_GL_PATH_BUILT
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
  if (const GlPathContexts* p = registered(path)) return p->make(target.device);
  throw InputError("--gl " + to_string(path) + ": this heightmarch's GLSL worker was built with " + with +
                   " alone (its library was not found when it was built)");
}

std::vector<GlDevice> list_gl_devices(GlPath path) {
  const GlPathContexts* p = registered(path);
  return p && p->devices ? p->devices() : std::vector<GlDevice>{};
}

}  // namespace heightmarch
