#pragma once
// A user's camera poses (--views FILE.csv): where their game's camera stands over a surface,
// read from a CSV file (docs/measures.md#view-sets).
#include <cstddef>
#include <string>
#include <vector>

namespace heightmarch {

// In the surface's frame: the plane z = 0 is the surface, its texture coordinate (u, v) = (x, y)
// (the map repeats over the plane), its normal +z. fov: the vertical field of view in degrees,
// as glm::perspective takes it; width x height: the image in pixels.
struct CameraPose {
  double eye[3], target[3], up[3];
  double fov_degrees;
  int width, height;
  std::size_t line;  // of its file, from 1: what a message about the pose names
};

inline constexpr int kMaxCameraPoses = 4096;

// Header eye_x,eye_y,eye_z,target_x,target_y,target_z,up_x,up_y,up_z,fov,width,height, one pose a
// line. Throws InputError naming the line for a malformed file: a wrong header or column count, a
// field that is no number, an eye not above the surface (eye_z <= 0), a target at the eye, an up
// along the view direction, a field of view outside (0, 180) degrees, a size outside [1,
// kMaxViewSide], no poses or more than kMaxCameraPoses.
std::vector<CameraPose> load_camera_poses(const std::string& path);

}  // namespace heightmarch
