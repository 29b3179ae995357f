#pragma once
// Which GL a GLSL run draws in: a path (how the worker gets its context) and, through EGL, a
// device; and what the context said it is (the renderer every GLSL figure is named by).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace heightmarch {

// The ways heightmarch-glsl-worker creates its GL context, the only thing they do differently
// (src/glsl/gl_context.hpp): one row each, and the only list of them.
// X(id, name, display name)
// - osmesa: Mesa's OSMesa, llvmpipe in the worker itself (removed from Mesa in 25.1);
// - egl: EGL's device platform (EGL_EXT_platform_device): Mesa's software device (llvmpipe) or a
//   GPU's own driver, headless.
#define HEIGHTMARCH_GL_PATHS(X) \
  X(osmesa, "osmesa", "OSMesa") \
  X(egl, "egl", "EGL")

#define HEIGHTMARCH_GL_PATH_ENUM(id, ...) id,
enum class GlPath { HEIGHTMARCH_GL_PATHS(HEIGHTMARCH_GL_PATH_ENUM) };
#undef HEIGHTMARCH_GL_PATH_ENUM

std::string to_string(GlPath path);     // "osmesa", "egl"
std::string display_name(GlPath path);  // "OSMesa", "EGL"
std::string gl_path_names();            // "osmesa|egl", for help texts
// InputError naming `option` for a name that is no path.
GlPath parse_gl_path(const std::string& name, const std::string& option);

struct GlTarget {
  // None: the worker's default, OSMesa where the worker was built with it, else EGL.
  std::optional<GlPath> path;
  // EGL only: "software" (Mesa's software device), an index or a name from list_gl_devices();
  // empty: EGL's first device.
  std::string device;
  bool operator==(const GlTarget&) const = default;
};

// InputError for a target no worker draws in: a device with OSMesa, or one that can be no
// device's name or index (names are file names, letters, digits and . _ -: software,
// renderD128; at most 64 bytes).
void check(const GlTarget& target);
// --gl and --gl-device as the command line gives them (empty: not given), checked; a device
// without --gl means EGL.
GlTarget parse_gl_target(const std::string& path, const std::string& device);

// What a worker's context is, as it said at start-up.
struct GlRenderer {
  GlPath path = GlPath::osmesa;
  std::string device;    // the device it runs on: "software", "renderD128", ...; OSMesa: "software"
  std::string renderer;  // GL_RENDERER: "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   // GL_VERSION: "4.5 (Core Profile) Mesa 22.3.6"
  std::string driver;    // GL_VENDOR: "Mesa/X.org", "NVIDIA Corporation"
  bool software = true;  // a CPU rasteriser: its draws are timed by the wall clock, a GPU's by timer queries

  // What results call the backend: "glsl (llvmpipe, LLVM 15.0.6, 256 bits; EGL)".
  std::string label() const;
  bool operator==(const GlRenderer&) const = default;
};

// One draw's time, both ways (docs/measurements.md).
struct GlDrawTime {
  double wall_seconds = 0;  // the draw and its glFinish, timed in the worker
  std::optional<double>
      timer_seconds;  // GL_TIME_ELAPSED around the draw; none where the driver answered none
  // The figure results use: on a software renderer (llvmpipe) the wall time, as the CPU's rows
  // are timed; on a GPU the timer query, the GPU's own time without the driver's overhead.
  double seconds(const GlRenderer& renderer) const {
    return renderer.software || !timer_seconds ? wall_seconds : *timer_seconds;
  }
};

// An EGL device as heightmarch-glsl-worker --list-devices finds it.
struct GlDevice {
  int index = 0;
  std::string name;        // "software", "renderD128", "card0" or "device3": what --gl-device takes
  std::string extensions;  // EGL's device extensions
  // Its context's GL_RENDERER and GL_VERSION, or why none could be made.
  std::string renderer, version, error;
};

}  // namespace heightmarch
