#include "heightmarch/gl_target.hpp"

#include <algorithm>
#include <cctype>

#include "heightmarch/error.hpp"

namespace heightmarch {

namespace {

struct PathRow {
  GlPath id;
  const char *name, *display;
};
#define HEIGHTMARCH_GL_PATH_ROW(id, name, display) {GlPath::id, name, display},
constexpr PathRow kPaths[] = {HEIGHTMARCH_GL_PATHS(HEIGHTMARCH_GL_PATH_ROW)};
#undef HEIGHTMARCH_GL_PATH_ROW

const PathRow& row(GlPath path) {
  for (const PathRow& r : kPaths)
    if (r.id == path) return r;
  throw std::logic_error("GL path " + std::to_string(int(path)) + " is none of the list's");
}

constexpr std::size_t kMaxDeviceBytes = 64;

}  // namespace

std::string to_string(GlPath path) { return row(path).name; }
std::string display_name(GlPath path) { return row(path).display; }

std::string gl_path_names() {
  std::string names;
  for (const PathRow& r : kPaths) names += (names.empty() ? "" : "|") + std::string(r.name);
  return names;
}

GlPath parse_gl_path(const std::string& name, const std::string& option) {
  for (const PathRow& r : kPaths)
    if (name == r.name) return r.id;
  throw InputError(option + " " + printable(name) + ": not a GL path (" + gl_path_names() + ")");
}

void check(const GlTarget& target) {
  const std::string& device = target.device;
  if (device.empty()) return;
  const bool name_like = std::all_of(device.begin(), device.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
  });
  if (device.size() > kMaxDeviceBytes || !name_like)
    throw InputError("--gl-device " + printable(device) +
                     ": not a device (software, an index or a name from heightmarch glsl --list-devices)");
  if (target.path == GlPath::osmesa)
    throw InputError("--gl-device " + device + ": OSMesa has no devices (it is llvmpipe); EGL has");
}

GlTarget parse_gl_target(const std::string& path, const std::string& device) {
  GlTarget target;
  if (!path.empty()) target.path = parse_gl_path(path, "--gl");
  target.device = device;
  check(target);
  if (!device.empty()) target.path = GlPath::egl;  // only EGL has devices
  return target;
}

std::string GlRenderer::label() const {
  // "llvmpipe (LLVM 15.0.6, 256 bits)" reads "llvmpipe, LLVM 15.0.6, 256 bits" inside the label's own
  // parentheses.
  std::string name = renderer;
  const std::size_t open = name.find(" (");
  if (open != std::string::npos && name.back() == ')' && name.find(')') == name.size() - 1)
    name = name.substr(0, open) + ", " + name.substr(open + 2, name.size() - open - 3);
  return "glsl (" + name + "; " + display_name(path) + ")";
}

}  // namespace heightmarch
