// Point contacts of a model with a terrain, as the integrator's contact stages (integrators/) and the
// trajectory optimiser's complementarity rows (trajopt/complementarity_rows.hpp) read them, the
// contact model of python/hovi/contact: points of bodies, a terrain
// with horizontal faces (normal +z), Coulomb friction mu on a polyhedral cone of d directions.
#pragma once
#include <vector>

#include "hovi/model/model.hpp"

namespace hovi {

// A ground plane at `ground` with gaps (no ground for x0 < x < x1, down to ground - depth) and
// boxes (top faces at `top` over x0 < x < x1, y0 < y < y1; boxes stand above gaps).
struct Terrain {
  struct Gap {
    double x0, x1, depth;
  };
  struct Box {
    double x0, x1, top, y0, y1;
  };
  double ground = 0;
  std::vector<Gap> gaps;
  std::vector<Box> boxes;
  // h(x, y), the height of the surface below (x, y) (piecewise constant: its gradient is zero).
  double height(double x, double y) const;
  // InputError naming the field unless every number is finite (y0, y1 may be infinite), x0 < x1,
  // y0 < y1 and depth > 0.
  void check() const;
};

// A contact of a body: the point (in the body's joint frame), or the centre of a sphere of `radius`
// (a round foot), which touches the terrain when the centre is `radius` above it.
struct ContactPoint {
  int body;
  Vec3 point;
  double radius = 0;
};

// The unknowns of a contact in a step (and its inputs in trajectory optimisation).
enum class ContactUnknown { Normal, Friction, Slack };

struct ContactModel {
  std::vector<ContactPoint> points;
  Terrain terrain;
  double mu = 0;  // friction coefficient
  MatX D;         // d x 3: the friction directions (horizontal unit vectors, +-x, +-y or +-x)

  int size() const { return static_cast<int>(points.size()); }
  int d() const { return static_cast<int>(D.rows()); }
  // The unknowns of contact c in a step: normal impulse λ_c, friction impulses β_c,1..d and the
  // sliding displacement γ_c (Stewart-Trinkle's slack), at c * per_contact() + 0, 1..d, d+1.
  int per_contact() const { return d() + 2; }
  int unknowns() const { return size() * per_contact(); }
  // The index of contact c's unknown `what` (friction: direction i) among the step's unknowns.
  int index(int c, ContactUnknown what, int i = 0) const {
    return c * per_contact() + (what == ContactUnknown::Normal ? 0 : what == ContactUnknown::Friction ? 1 + i : 1 + d());
  }
  // The height contact c's point (its centre) keeps above the terrain at (x, y): the terrain's height
  // plus the contact's radius; its gap φ_c at the point's world position x is x.z - surface(c, x).
  double surface(int c, const Vec3& x) const { return terrain.height(x[0], x[1]) + points[c].radius; }
  double gap(int c, const Vec3& x) const { return x[2] - surface(c, x); }
  // The world impulse of contact c for the step's unknowns z: λ_c e_z + D^T β_c.
  Vec3 world_impulse(const Eigen::Ref<const VecX>& z, int c) const {
    return z[index(c, ContactUnknown::Normal)] * Vec3::UnitZ() +
           D.transpose() * z.segment(index(c, ContactUnknown::Friction), d());
  }
  // ModelError / InputError naming the problem unless every point is on an existing body with mass,
  // finite, mu is finite in [0, 1e3], D holds horizontal unit vectors and the terrain is valid.
  void check(const Model& model) const;
  // The points in their bodies' COM frames, 3 x size() (Model::point_in_com_frame).
  MatX points_in_com_frames(const Model& model) const;
};

}  // namespace hovi
