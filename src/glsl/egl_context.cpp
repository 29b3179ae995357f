// The EGL path: a headless context on one of EGL's devices (EGL_EXT_device_enumeration,
// EGL_EXT_platform_device), with no surface (EGL_KHR_surfaceless_context): Mesa's software
// device (llvmpipe) where Mesa is installed, and a GPU's own driver where its EGL vendor library
// is (NVIDIA's runs headless this way).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "glsl/gl_context.hpp"
#include "heightmarch/error.hpp"

namespace heightmarch {
namespace {

// Whether a space-separated extension list names `extension` (a whole word).
bool has_extension(const char* list, const std::string& extension) {
  std::istringstream words(list ? list : "");
  std::string word;
  while (words >> word)
    if (word == extension) return true;
  return false;
}

std::string egl_error() {
  char text[32];
  std::snprintf(text, sizeof text, "EGL error 0x%04x", unsigned(eglGetError()));
  return text;
}

// The device functions EGL 1.5 offers only as extensions.
struct DeviceApi {
  PFNEGLQUERYDEVICESEXTPROC query_devices = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;
};

const DeviceApi& device_api() {
  static const DeviceApi api = [] {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    for (const char* needed :
         {"EGL_EXT_device_enumeration", "EGL_EXT_device_query", "EGL_EXT_platform_device"})
      if (!has_extension(client, needed))
        throw std::runtime_error(
            std::string("EGL: the EGL library lacks ") + needed +
            " (is libEGL from libglvnd with a vendor library, such as libegl-mesa0, installed?)");
    DeviceApi a;
    a.query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    a.query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    a.get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!a.query_devices || !a.query_device_string || !a.get_platform_display)
      throw std::runtime_error("EGL: the EGL library names device extensions it does not define");
    return a;
  }();
  return api;
}

struct EglDevice {
  EGLDeviceEXT handle;
  std::string name, extensions;
  bool software;
};

std::string base_name(const char* path) {
  const std::string p = path;
  return p.substr(p.find_last_of('/') + 1);
}

// EGL's devices in its order, named as --gl-device takes them: "software" for Mesa's software
// device, else its DRM render node's file name, else its DRM device file's, else "deviceN".
std::vector<EglDevice> egl_devices() {
  const DeviceApi& api = device_api();
  constexpr EGLint kMaxDevices = 64;  // more than any machine has
  EGLDeviceEXT handles[kMaxDevices];
  EGLint count = 0;
  if (!api.query_devices(kMaxDevices, handles, &count))
    throw std::runtime_error("EGL: eglQueryDevicesEXT failed (" + egl_error() + ")");
  std::vector<EglDevice> devices;
  for (EGLint i = 0; i < count; ++i) {
    const char* extensions = api.query_device_string(handles[i], EGL_EXTENSIONS);
    EglDevice d{handles[i], "device" + std::to_string(i), extensions ? extensions : "",
                has_extension(extensions, "EGL_MESA_device_software")};
    const char* file = nullptr;
    if (has_extension(extensions, "EGL_EXT_device_drm_render_node"))
      file = api.query_device_string(handles[i], EGL_DRM_RENDER_NODE_FILE_EXT);
    if (!file && has_extension(extensions, "EGL_EXT_device_drm"))
      file = api.query_device_string(handles[i], EGL_DRM_DEVICE_FILE_EXT);
    if (d.software)
      d.name = "software";
    else if (file && *file)
      d.name = base_name(file);
    devices.push_back(d);
  }
  return devices;
}

std::string device_list(const std::vector<EglDevice>& devices) {
  std::string list;
  for (std::size_t i = 0; i < devices.size(); ++i)
    list += (i ? ", " : "") + std::to_string(i) + " " + devices[i].name;
  return list.empty() ? "none" : list;
}

// The device --gl-device names: empty, EGL's first; an index; or a name.
const EglDevice& pick(const std::vector<EglDevice>& devices, const std::string& spec) {
  if (devices.empty())
    throw std::runtime_error(
        "EGL lists no devices (install Mesa's EGL vendor library, libegl-mesa0, or a GPU driver's)");
  if (spec.empty()) return devices.front();
  if (std::all_of(spec.begin(), spec.end(), [](char c) { return c >= '0' && c <= '9'; }) && spec.size() < 4 &&
      std::stoul(spec) < devices.size())
    return devices[std::stoul(spec)];
  for (const EglDevice& d : devices)
    if (d.name == spec) return d;
  throw InputError("--gl-device " + spec + ": EGL lists no such device; it lists " + device_list(devices) +
                   " (heightmarch glsl --list-devices)");
}

class EglContext : public GlContext {
 public:
  explicit EglContext(const EglDevice& device) : GlContext(GlPath::egl, device.name, device.software) {
    const std::string where = "EGL device " + device.name + ": ";
    display_ = device_api().get_platform_display(EGL_PLATFORM_DEVICE_EXT, device.handle, nullptr);
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, nullptr, nullptr))
      throw std::runtime_error(where + "no display (" + egl_error() + ")");
    try {
      if (!has_extension(eglQueryString(display_, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
        throw std::runtime_error(where + "no EGL_KHR_surfaceless_context (a context without a surface)");
      // Any surface type (the default asks for windows, which a device has none of): none is made.
      const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLConfig config = nullptr;
      EGLint configs = 0;
      if (!eglBindAPI(EGL_OPENGL_API) ||
          !eglChooseConfig(display_, config_attributes, &config, 1, &configs) || configs < 1)
        throw std::runtime_error(where + "no desktop OpenGL (" + egl_error() + ")");
      const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                           3,
                                           EGL_CONTEXT_MINOR_VERSION,
                                           3,
                                           EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                           EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                           EGL_NONE};
      context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attributes);
      if (context_ == EGL_NO_CONTEXT || !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw std::runtime_error(where + "could not create a GL 3.3 core context (" + egl_error() + ")");
    } catch (...) {
      release();
      throw;
    }
  }
  ~EglContext() override { release(); }

  void* proc_address(const char* name) const override {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
  }

 private:
  void release() {
    if (context_ != EGL_NO_CONTEXT) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display_, context_);
      context_ = EGL_NO_CONTEXT;
    }
    eglTerminate(display_);
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

std::unique_ptr<GlContext> make_egl_context(const std::string& device) {
  return std::make_unique<EglContext>(pick(egl_devices(), device));
}

std::vector<GlDevice> list_egl_devices() {
  std::vector<GlDevice> out;
  const std::vector<EglDevice> devices = egl_devices();
  for (std::size_t i = 0; i < devices.size(); ++i) {
    GlDevice d{int(i), devices[i].name, devices[i].extensions, "", "", ""};
    try {
      const EglContext context(devices[i]);
      const auto get_string = reinterpret_cast<PFNGLGETSTRINGPROC>(context.proc_address("glGetString"));
      const GLubyte* renderer = get_string ? get_string(GL_RENDERER) : nullptr;
      const GLubyte* version = get_string ? get_string(GL_VERSION) : nullptr;
      d.renderer = renderer ? reinterpret_cast<const char*>(renderer) : "";
      d.version = version ? reinterpret_cast<const char*>(version) : "";
    } catch (const std::exception& e) {
      d.error = e.what();
    }
    out.push_back(d);
  }
  return out;
}

[[maybe_unused]] const bool registered = register_gl_path({GlPath::egl, make_egl_context, list_egl_devices});

}  // namespace
}  // namespace heightmarch
