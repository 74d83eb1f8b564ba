#include "hovi/model/contact_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "hovi/errors.hpp"

namespace hovi {

double Terrain::height(double x, double y) const {
  double h = ground;
  for (const Gap& g : gaps)
    if (x > g.x0 && x < g.x1) h = ground - g.depth;
  for (const Box& b : boxes)
    if (x > b.x0 && x < b.x1 && y > b.y0 && y < b.y1) h = std::max(h, b.top);
  return h;
}

void Terrain::check() const {
  auto finite = [](double v, const std::string& what) {
    if (!std::isfinite(v)) throw InputError("terrain " + what + " must be a finite number, got " + std::to_string(v));
  };
  finite(ground, "ground");
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    const std::string name = "gaps[" + std::to_string(i) + "]";
    finite(gaps[i].x0, name + ".x0");
    finite(gaps[i].x1, name + ".x1");
    finite(gaps[i].depth, name + ".depth");
    if (!(gaps[i].x0 < gaps[i].x1) || !(gaps[i].depth > 0))
      throw InputError("terrain " + name + " needs x0 < x1 and depth > 0");
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const std::string name = "boxes[" + std::to_string(i) + "]";
    finite(boxes[i].x0, name + ".x0");
    finite(boxes[i].x1, name + ".x1");
    finite(boxes[i].top, name + ".top");
    if (std::isnan(boxes[i].y0) || std::isnan(boxes[i].y1))
      throw InputError("terrain " + name + " has a NaN y0 or y1");
    if (!(boxes[i].x0 < boxes[i].x1) || !(boxes[i].y0 < boxes[i].y1))
      throw InputError("terrain " + name + " needs x0 < x1 and y0 < y1");
  }
}

void ContactModel::check(const Model& model) const {
  if (points.empty()) throw InputError("contacts: give at least one contact point");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int b = points[i].body;
    const std::string name = "contact point " + std::to_string(i);
    if (b < 0 || b >= model.n())
      throw ModelError(name + ": body index " + std::to_string(b) + " is not a body of this model (it has " +
                       std::to_string(model.n()) + ")");
    if (!(model.spec[b].mass > 0))
      throw ModelError(name + ": body '" + model.spec[b].name +
                       "' has no mass (a contact force on a massless body has nothing to act on; put the point on "
                       "the massive body it is fixed to)");
    if (!points[i].point.allFinite()) throw InputError(name + ": the point must be finite");
    if (!(points[i].radius >= 0) || !std::isfinite(points[i].radius))
      throw InputError(name + ": the radius must be a finite number >= 0, got " + std::to_string(points[i].radius));
  }
  if (!std::isfinite(mu) || mu < 0 || mu > 1e3)
    throw InputError("mu must be a finite friction coefficient in [0, 1000], got " + std::to_string(mu));
  if (D.cols() != 3 || D.rows() < 1) throw InputError("friction directions must be a (d, 3) array, d >= 1");
  for (int i = 0; i < D.rows(); ++i)
    if (!D.row(i).allFinite() || std::abs(D(i, 2)) > 1e-12 || std::abs(D.row(i).norm() - 1) > 1e-12)
      throw InputError("friction direction " + std::to_string(i) + " must be a horizontal unit vector");
  terrain.check();
}

MatX ContactModel::points_in_com_frames(const Model& model) const {
  MatX r(3, size());
  for (int c = 0; c < size(); ++c) r.col(c) = model.point_in_com_frame(points[c].body, points[c].point);
  return r;
}

}  // namespace hovi
