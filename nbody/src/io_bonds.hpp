/// @file io_bonds.hpp
/// The bonds of a checkpoint with their state (/ssdem_state/bonds, layout in ssdem/io.hpp).
#pragma once
#include <string>

#include "common/h5.hpp"
#include "ssdem/bonds.hpp"

namespace ssdem {

/// Write the group `bonds` under `state` (an open /ssdem_state): this process's rows `rows` of
/// every bond array (b holds exactly those rows), the attributes released_energy = `released`
/// (the total) and released_base = b.released_base (the same on every process). False if a data
/// write failed.
bool write_bond_state(hid_t state, const BondSet& b, const common::h5::RowBlock& rows, double released);
/// Read /ssdem_state/bonds of the open file `f` (`path` names it in errors: InputError).
BondSet read_bond_state(hid_t f, const std::string& path);

}  // namespace ssdem
