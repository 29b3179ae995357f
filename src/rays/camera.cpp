#include "rays/camera.hpp"

#include <cmath>

namespace heightmarch {
namespace {

constexpr double kTutorialEyeZ = 3.0, kTutorialFovDegrees = 45.0;

Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 normalized(const Vec3& a) {
  const double len = std::sqrt(dot(a, a));
  return {a.x / len, a.y / len, a.z / len};
}

// A camera given in world space, seen from a surface frame (origin o, orthonormal tangent,
// bitangent and normal): the same camera in that frame's coordinates.
Camera in_frame(const Camera& world, const Vec3& o, const Vec3& t, const Vec3& b, const Vec3& n) {
  const auto axis = [&](const Vec3& v) { return Vec3{dot(v, t), dot(v, b), dot(v, n)}; };
  Camera c = world;
  c.eye = axis(world.eye - o);
  c.right = axis(world.right);
  c.up = axis(world.up);
  c.forward = axis(world.forward);
  return c;
}

}  // namespace

// Eye height h and distance a before the near edge follow from tan near = a / h and
// tan far = (1 + a) / h.
Camera default_camera(double near_degrees, double far_degrees) {
  const double near_angle = near_degrees * kPi / 180.0, far_angle = far_degrees * kPi / 180.0;
  const double height = 1.0 / (std::tan(far_angle) - std::tan(near_angle));
  const double back = std::tan(near_angle) * height;
  const double pitch = 0.5 * (far_angle + near_angle);  // forward, from straight down
  Camera c;
  c.eye = {0.5, -back, height};
  c.right = {1, 0, 0};
  c.up = {0, std::cos(pitch), std::sin(pitch)};
  c.forward = {0, std::sin(pitch), -std::cos(pitch)};
  c.tan_half_fov = std::tan(0.5 * (far_angle - near_angle));
  return c;
}

Camera tutorial_camera(double seconds) {
  const double angle = kTutorialDegreesPerSecond * seconds * kPi / 180.0;
  const double k = 1.0 / std::sqrt(2.0);  // normalize(1, 0, 1)
  const double c = std::cos(angle), s = std::sin(angle), C = 1.0 - c;
  const double ax = k, ay = 0, az = k;
  // Rodrigues' rotation matrix, its columns: the quad's tangent, bitangent and normal in the world.
  const Vec3 t{c + ax * ax * C, ay * ax * C + az * s, az * ax * C - ay * s};
  const Vec3 b{ax * ay * C - az * s, c + ay * ay * C, az * ay * C + ax * s};
  const Vec3 n{ax * az * C + ay * s, ay * az * C - ax * s, c + az * az * C};
  Camera world;
  world.eye = {0, 0, kTutorialEyeZ};
  world.right = {1, 0, 0};
  world.up = {0, 1, 0};
  world.forward = {0, 0, -1};
  world.tan_half_fov = std::tan(0.5 * kTutorialFovDegrees * kPi / 180.0);
  return in_frame(world, {0, 0, 0}, t, b, n);
}

Camera pose_camera(const CameraPose& p) {
  Camera c;
  c.eye = {p.eye[0], p.eye[1], p.eye[2]};
  c.forward = normalized(Vec3{p.target[0], p.target[1], p.target[2]} - c.eye);
  c.right = normalized(cross(c.forward, {p.up[0], p.up[1], p.up[2]}));
  c.up = cross(c.right, c.forward);
  c.tan_half_fov = std::tan(0.5 * p.fov_degrees * kPi / 180.0);
  return c;
}

Ray camera_ray(const Camera& cam, const PlaneMap& plane, double image_x, double image_y, int width,
               int height) {
  const double sx = (2.0 * image_x / width - 1.0) * cam.tan_half_fov * double(width) / double(height);
  const double sy = (1.0 - 2.0 * image_y / height) * cam.tan_half_fov;  // row 0 = top of the image
  const double dx = cam.forward.x + sx * cam.right.x + sy * cam.up.x;
  const double dy = cam.forward.y + sx * cam.right.y + sy * cam.up.y;
  const double dz = cam.forward.z + sx * cam.right.z + sy * cam.up.z;
  if (dz >= 0.0) return {false, 0, 0, 0, 0, 0};
  const double t = -cam.eye.z / dz;
  const double x = cam.eye.x + t * dx, y = cam.eye.y + t * dy;
  if (x < plane.x0 || x > plane.x1 || y < plane.y0 || y > plane.y1) return {false, 0, 0, 0, 0, 0};
  const double ex = cam.eye.x - x, ey = cam.eye.y - y, ez = cam.eye.z;
  const double len = std::sqrt(ex * ex + ey * ey + ez * ez);
  if (ez / len < plane.min_view_z) return {false, 0, 0, 0, 0, 0};
  return {true,
          float(plane.u0 + plane.scale * x),
          float(plane.v0 + plane.scale * y),
          float(ex / len),
          float(ey / len),
          float(ez / len)};
}

}  // namespace heightmarch
