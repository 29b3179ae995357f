#pragma once
// Where the worker's GL context comes from: the one thing the GL paths (heightmarch/gl_target.hpp)
// do differently. Everything after it, the framebuffer, programs, uniforms, draws and read-back,
// is GlRunner's, the same for every path.
#include <memory>
#include <string>
#include <vector>

#include "heightmarch/gl_target.hpp"

namespace heightmarch {

class GlContext {
 public:
  virtual ~GlContext() = default;
  // A GL function of the context's own library; null where it has none of that name.
  virtual void* proc_address(const char* name) const = 0;
  GlPath path() const { return path_; }
  const std::string& device() const { return device_; }  // "software", "renderD128", ...
  bool software() const { return software_; }            // a CPU rasteriser (llvmpipe)

 protected:
  GlContext(GlPath path, std::string device, bool software)
      : path_(path), device_(std::move(device)), software_(software) {}

 private:
  GlPath path_;
  std::string device_;
  bool software_;
};

// What a GL path's file (osmesa_context.cpp, egl_context.cpp) gives the worker, which CMake
// compiles in only where it found the path's library: its contexts and, for a path that offers a
// choice, its devices. The file registers it, once, at namespace scope:
//   [[maybe_unused]] const bool registered = register_gl_path({GlPath::egl, make_egl_context,
//   list_egl_devices});
struct GlPathContexts {
  GlPath path;
  std::unique_ptr<GlContext> (*make)(const std::string& device);
  std::vector<GlDevice> (*devices)() = nullptr;  // null: the path has one device
};
bool register_gl_path(const GlPathContexts& contexts);

// The paths this worker was built with (those registered: CMake's HEIGHTMARCH_WITH_OSMESA and
// HEIGHTMARCH_WITH_EGL, the libraries it found), in HEIGHTMARCH_GL_PATHS's order; at least one.
std::vector<GlPath> built_gl_paths();

// A GL 3.3 core context of the target, current on the calling thread, with llvmpipe at `threads`
// threads (llvmpipe reads LP_NUM_THREADS once, at the process's first context: one per process;
// a GPU ignores it). InputError for a path this worker was built without or a device EGL does not
// list; std::runtime_error when the library makes no context.
std::unique_ptr<GlContext> make_gl_context(const GlTarget& target, int threads);

// A path's devices, each tried with a context for its renderer string (one process lists them: a
// context is made and destroyed per device). Empty for a path the worker was built without or one
// without a choice of device.
std::vector<GlDevice> list_gl_devices(GlPath path);

}  // namespace heightmarch
