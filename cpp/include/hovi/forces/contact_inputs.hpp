// The contacts' unknowns as control inputs of the model (contact-implicit trajectory optimisation):
// a force at each contact point scaled by its normal and friction inputs, and a slack without force.
#pragma once
#include "hovi/model/contact_model.hpp"
#include "hovi/model/model.hpp"

namespace hovi {

// `model` with the contacts' unknowns appended as controls m + contacts.index(c, what, i): λ_c a
// world force +z at the point, β_c,i a world force D_i there, γ_c none. ModelError unless
// contacts.check(model) holds.
Model with_contact_inputs(const Model& model, const ContactModel& contacts);

}  // namespace hovi
