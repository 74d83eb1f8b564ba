// A Model as bytes and back (Python: pickling hovi.Model, so that models travel to other
// processes and cluster workers): every field, bit for bit, so that the copy computes exactly
// what the original does. The force elements and constraints write their own parameters (their
// save()); only hovi's own kinds can be read back, and a kind defined elsewhere cannot be saved.
#pragma once
#include <string>

#include "hovi/model/model.hpp"

namespace hovi {

std::string serialize(const Model& model);
// The bytes: a header (magic, format version, byte order, length and FNV-1a checksum of the
// payload) and the payload (every field in order).
// Throws ModelError if the bytes are not a serialised model of this format (or were written on a
// machine of the other byte order), are truncated, do not match their checksum ("model bytes are
// corrupted (checksum mismatch)": a changed byte is never read as another model), or describe an
// invalid model (the model is rebuilt through add_body, add_wrench, add_constraint and add_visual,
// which check it).
Model deserialize(const std::string& bytes);

}  // namespace hovi
