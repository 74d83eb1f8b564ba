#include "hovi/model/constraint.hpp"

#include "hovi/errors.hpp"

namespace hovi {

void Constraint::save(ByteWriter&) const {
  throw ModelError(std::string("a constraint of kind '") + kind() + "' cannot be serialised (it does not implement save)");
}

}  // namespace hovi
