/// @file bond_columns.hpp
/// Append one bond's ids and constant columns (bond_file.hpp) to any structure of arrays with these
/// members: common::BondTable (the file's bonds) and ssdem::BondSet (nbody/include/ssdem/bonds.hpp,
/// which adds the dynamic bond state).
#pragma once
#include <cstdint>

namespace common {

template <class T>
void push_bond_columns(T& t, std::uint64_t a, std::uint64_t b, double kn, double ks, double sc, double tc, double rb,
                       double L0) {
  t.id_a.push_back(a);
  t.id_b.push_back(b);
  t.kn.push_back(kn);
  t.ks.push_back(ks);
  t.sigma_c.push_back(sc);
  t.tau_c.push_back(tc);
  t.radius.push_back(rb);
  t.length0.push_back(L0);
}

}  // namespace common
