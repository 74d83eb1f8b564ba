// The contact model shared by the bindings (hovi._core.ContactModel: the integrator's contact stages,
// the trajectory optimiser's complementarity rows).
#pragma once
#include <vector>

#include "common.hpp"
#include "hovi/model/contact_model.hpp"

namespace hovi::py_bind {

// The terrain of its ground height, gaps (G, 3) rows (x0, x1, depth) and boxes (B, 5) rows (x0, x1, top,
// y0, y1), checked; the contact model of hovi.contact.Contacts' arrays: bodies (C,), points (C, 3) in
// the bodies' joint frames, the terrain, mu, friction directions (d, 3).
Terrain terrain(double ground, const ArrayLike& gaps, const ArrayLike& boxes);
ContactModel contact_model(const std::vector<int>& bodies, const ArrayLike& points, const Terrain& terrain, double mu,
                           const ArrayLike& directions, const OptArrayLike& radii);

}  // namespace hovi::py_bind
