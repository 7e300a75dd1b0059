/// @file choices.cpp
/// The solver's string choices: update scheme (usl, usf, musl) and grid face type (free, fixed,
/// symmetry), parsed from the scene (declarations in mpm/solver.hpp).
#include <stdexcept>
#include <string>

#include "mpm/solver.hpp"

namespace mpmfrag {

Scheme parse_scheme(const std::string& s) {
  if (s == "usl") return Scheme::usl;
  if (s == "usf") return Scheme::usf;
  if (s == "musl") return Scheme::musl;
  throw std::invalid_argument("unknown update scheme '" + s + "' (usl, usf, musl)");
}
const char* scheme_name(Scheme s) {
  return s == Scheme::usl ? "usl" : s == Scheme::usf ? "usf" : "musl";
}
BoundaryType parse_boundary(const std::string& s) {
  if (s == "free") return BoundaryType::free;
  if (s == "fixed") return BoundaryType::fixed;
  if (s == "symmetry") return BoundaryType::symmetry;
  throw std::invalid_argument("unknown boundary type '" + s + "' (free, fixed, symmetry)");
}

}  // namespace mpmfrag
