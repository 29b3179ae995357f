// The names a user gives views and view sets, turned into their typed values (views.hpp).
#include <charconv>
#include <stdexcept>
#include <string>

#include "heightmarch/error.hpp"
#include "heightmarch/views.hpp"

namespace heightmarch {

ViewSpec parse_view(const std::string& text, int width, int height) {
  ViewSpec view = default_view(width, height);
  if (text == "default") return view;
  if (text.rfind("default:", 0) == 0) {
    parse_view_angles(text.substr(8), view);
    return view;
  }
  const std::string prefix = "sweep:";
  if (text.rfind(prefix, 0) != 0)
    throw InputError("unknown view '" + text + "' (default, default:NEAR-FAR or sweep:THETA[,PHI])");
  view.kind = ViewSpec::Kind::sweep;
  const std::string args = text.substr(prefix.size());
  const auto comma = args.find(',');
  try {
    std::size_t used = 0;
    const std::string theta = args.substr(0, comma);
    view.theta_degrees = std::stof(theta, &used);
    if (used != theta.size()) throw std::invalid_argument("trailing");
    if (comma != std::string::npos) {
      const std::string phi = args.substr(comma + 1);
      view.phi_degrees = std::stof(phi, &used);
      if (used != phi.size()) throw std::invalid_argument("trailing");
    }
  } catch (const std::logic_error&) {
    throw InputError("view '" + text + "': THETA and PHI must be numbers in degrees");
  }
  if (!(view.theta_degrees >= 0.0f && view.theta_degrees <= 89.0f))
    throw InputError("view '" + text + "': THETA must be in [0, 89] degrees");
  if (!std::isfinite(view.phi_degrees))
    throw InputError("view '" + text + "': PHI must be a finite number of degrees");
  return view;
}

void parse_view_angles(const std::string& text, ViewSpec& view) {
  const auto dash = text.find('-', 1);
  float near = 0, far = 0;
  try {
    if (dash == std::string::npos) throw std::invalid_argument("no dash");
    std::size_t used_near = 0, used_far = 0;
    const std::string a = text.substr(0, dash), b = text.substr(dash + 1);
    near = std::stof(a, &used_near);
    far = std::stof(b, &used_far);
    if (used_near != a.size() || used_far != b.size()) throw std::invalid_argument("trailing");
  } catch (const std::logic_error&) {
    throw InputError("view angles '" + text + "' must be NEAR-FAR in degrees, e.g. 30-80");
  }
  if (!(near >= 0.0f && near < far && far <= kMaxViewDegrees))
    throw InputError("view angles '" + text + "' must satisfy 0 <= NEAR < FAR <= " +
                     std::to_string(int(kMaxViewDegrees)) + " degrees");
  view.near_degrees = near;
  view.far_degrees = far;
}

ViewSet parse_view_set(const std::string& text) {
  if (text == "single") return ViewSet::single();
  if (text == "around") return ViewSet::around();
  const std::string tutorial = "tutorial";
  if (text == tutorial) return ViewSet::tutorial();
  if (text.rfind(tutorial + ":", 0) == 0) {
    const std::string number = text.substr(tutorial.size() + 1);
    int frames = 0;
    const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), frames);
    if (number.empty() || ec != std::errc() || end != number.data() + number.size() || frames < 1 ||
        frames > kMaxSetViews)
      throw InputError("view set '" + text + "': tutorial:N takes a whole number of frames N in [1, " +
                       std::to_string(kMaxSetViews) + "]");
    return ViewSet::tutorial(frames);
  }
  if (text.size() > 4 && text.compare(text.size() - 4, 4, ".csv") == 0) return ViewSet::poses(text);
  throw InputError("unknown view set '" + text +
                   "' (single, around, tutorial[:N] or a camera-pose FILE.csv)");
}

}  // namespace heightmarch
