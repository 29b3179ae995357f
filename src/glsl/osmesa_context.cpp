// The OSMesa path: llvmpipe inside the worker itself, with a 4x4 RGBA buffer that OSMesa needs
// bound (the draws go to GlRunner's framebuffer).
#include <GL/osmesa.h>

#include <stdexcept>
#include <vector>

#include "glsl/gl_context.hpp"

namespace heightmarch {
namespace {

class OsmesaContext : public GlContext {
 public:
  OsmesaContext() : GlContext(GlPath::osmesa, "software", true) {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              3,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              3,
                              0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_ || !OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 4, 4)) {
      if (context_) OSMesaDestroyContext(context_);
      throw std::runtime_error("OSMesa: could not create a GL 3.3 core context");
    }
  }
  ~OsmesaContext() override { OSMesaDestroyContext(context_); }

  void* proc_address(const char* name) const override {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
  }

 private:
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(4 * 4 * 4);
};

// OSMesa has one device, its software rasteriser (check() refuses --gl-device with it).
std::unique_ptr<GlContext> make_osmesa_context(const std::string&) {
  return std::make_unique<OsmesaContext>();
}

[[maybe_unused]] const bool registered = register_gl_path({GlPath::osmesa, make_osmesa_context});

}  // namespace

}  // namespace heightmarch
