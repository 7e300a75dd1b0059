/// @file style.hpp
/// Material style "tonge_ramesh" of mpm-frag: the Tonge–Ramesh brittle-damage model (Tonge &
/// Ramesh 2016; El Mir, Ramesh & Richardson 2019) behind the batched material interface
/// (mpm/material.hpp). The point-wise physics lives in point_update.hpp; this adapter maps the
/// SoA particle arrays and the style's state fields onto it.
#pragma once
#include <memory>

#include "mpm/material.hpp"
#include "mpm/tonge_ramesh/params.hpp"

namespace mpmfrag {

/// Flaw-bin slots per particle declared by the style (state fields are static per style):
/// the bins of all populations together must not exceed this (El Mir 2019: 25 + 25).
inline constexpr int kTongeRameshBinSlots = 50;

/// Register "tonge_ramesh" (one line in register_builtin_materials).
void register_tonge_ramesh(MaterialRegistry& reg);

/// Direct constructor (tests, benchmarks).
std::unique_ptr<Material> make_tonge_ramesh(const tonge_ramesh::Params& p);

/// The style's state fields in order (damage, distension, iel, granular_strain, granular_energy,
/// localized, flaw_density[50], flaw_size[50], wing_length[50], damage_substeps: the cost field
/// of the MPI cuts, StateField::work).
std::vector<StateField> tonge_ramesh_state_fields();

}  // namespace mpmfrag
