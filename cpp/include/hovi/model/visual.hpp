// Visual geometry of a body (URDF <visual>): metadata for viewers, no effect on the dynamics.
#pragma once
#include <optional>
#include <string>

#include "hovi/spatial/algebra.hpp"

namespace hovi {

enum class VisualShape { Box, Cylinder, Sphere, Mesh };

struct Visual {
  int body = -1;               // body index; -1 = the world (links welded to a fixed base)
  std::string link;            // the URDF link it came from (merged fixed links keep their own name)
  VisualShape shape = VisualShape::Box;
  Vec3 size = Vec3::Zero();    // box: x, y, z; cylinder: radius, length, 0 (axis z); sphere: radius, 0, 0
  std::string filename;        // mesh: package://, absolute, or made absolute against the URDF's directory
  Vec3 scale = Vec3::Ones();   // mesh scale
  SE3 origin;                  // shape frame in the body's joint frame
  std::optional<Eigen::Vector4d> rgba;  // material colour, when the URDF gives one
};

// Throws ModelError naming the visual unless its sizes, scale, origin and colour are finite and valid.
void check_visual(const Visual& visual, int n_bodies);

}  // namespace hovi
