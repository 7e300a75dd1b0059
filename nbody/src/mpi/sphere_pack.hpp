/// @file sphere_pack.hpp
/// One sphere of a Spheres set (every array of Spheres::zip_arrays) appended to / read from a
/// byte buffer: the records of exchanges and of the packed local state (domain_sim.hpp).
#pragma once
#include <type_traits>
#include <vector>

#include "common/mpi_comm.hpp"
#include "ssdem/spheres.hpp"

namespace ssdem::mpi {

inline void put_sphere(const Spheres& sp, std::size_t i, std::vector<char>& b) {
  sp.for_each_array([&](const common::SphereArray&, const auto& arr) { common::mpi::put(b, arr[i]); });
}
inline void get_sphere(const std::vector<char>& b, std::size_t& off, Spheres& sp, std::size_t at) {
  sp.for_each_array([&](const common::SphereArray&, auto& arr) {
    using T = typename std::decay_t<decltype(arr)>::value_type;
    arr[at] = common::mpi::get<T>(b, off);
  });
}
inline void append_sphere(const std::vector<char>& b, std::size_t& off, Spheres& sp) {
  sp.resize(sp.size() + 1);
  get_sphere(b, off, sp, sp.size() - 1);
}

}  // namespace ssdem::mpi
