#include "glsl/gl_functions.hpp"

#include <stdexcept>
#include <string>

namespace heightmarch::gl {

#define HEIGHTMARCH_GL_DEFINE(type, name) type name = nullptr;
HEIGHTMARCH_GL_FUNCTIONS(HEIGHTMARCH_GL_DEFINE)
#undef HEIGHTMARCH_GL_DEFINE

void load_functions(const std::function<void*(const char*)>& proc_address) {
#define HEIGHTMARCH_GL_LOAD(type, name)               \
  name = reinterpret_cast<type>(proc_address(#name)); \
  if (!name) throw std::runtime_error("the GL library has no " #name " (a GL 3.3 core function)");
  HEIGHTMARCH_GL_FUNCTIONS(HEIGHTMARCH_GL_LOAD)
#undef HEIGHTMARCH_GL_LOAD
}

}  // namespace heightmarch::gl
