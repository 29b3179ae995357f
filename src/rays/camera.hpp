#pragma once
// Pinhole cameras in the surface's frame (the surface is the plane z = 0, its normal +z) and the
// ray each pixel sees: the default view's, LearnOpenGL's rotating quad's and a user's poses'.
#include "rays/batch_builder.hpp"
#include "rays/camera_poses.hpp"

namespace heightmarch {

inline constexpr double kPi = 3.14159265358979323846;

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// The eye, the image's unit axes and the forward direction, tan of half the vertical field of view.
struct Camera {
  Vec3 eye, right, up, forward;
  double tan_half_fov = 1;
};

// Where the plane shows the map: within [x0, x1] x [y0, y1], uv = (u0, v0) + scale (x, y). The
// pose files' plane is unbounded (every pixel that sees it, up to kMaxViewDegrees from the normal).
struct PlaneMap {
  double u0 = 0, v0 = 0, scale = 1;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double min_view_z = 0;  // rays more grazing than this are dropped
};

// The default camera: the near edge of the plane (v = 0) seen at near_degrees from the normal, the
// far edge (v = 1) at far_degrees, on the centre line.
Camera default_camera(double near_degrees, double far_degrees);
// LearnOpenGL's parallax scene: the quad turns at 10 degrees a second (glfwGetTime() * -10.0f)
// about normalize(1, 0, 1), seen from (0, 0, 3) with a 45 degree field of view at 800 x 600.
inline constexpr double kTutorialDegreesPerSecond = -10.0;
// That scene at `seconds` into the turn, in the quad's frame: the quad spans [-1, 1]^2 with uv
// (x + 1) / 2, (y + 1) / 2, tangent +x and bitangent +y of its model matrix. An eye behind the
// quad sees its back face, which is dropped (every ray then misses).
Camera tutorial_camera(double seconds);
Camera pose_camera(const CameraPose& pose);

// The ray through (image_x, image_y) of a width x height image, in pixels from its top left corner
// (pixel (px, py)'s centre is (px + 0.5, py + 0.5)), towards the eye, where it meets the plane
// within the map; a miss otherwise.
Ray camera_ray(const Camera& camera, const PlaneMap& plane, double image_x, double image_y, int width,
               int height);

}  // namespace heightmarch
