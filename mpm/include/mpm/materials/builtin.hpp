/// @file builtin.hpp
/// Registration functions of the builtin material styles (called by register_builtin_materials).
#pragma once
#include "mpm/material.hpp"

namespace mpmfrag {
/// "elastic": small-strain linear elasticity with the Hughes–Winget objective rate.
void register_elastic(MaterialRegistry& reg);
/// "neo_hookean": compressible neo-Hookean (Uintah cnh_mms form).
void register_neo_hookean(MaterialRegistry& reg);
/// "tillotson": Tillotson EOS pressure + elastic deviatoric stress (basalt defaults).
void register_tillotson(MaterialRegistry& reg);
}  // namespace mpmfrag

namespace mpmfrag {
/// Direct constructors (tests, benchmarks): density [kg/m^3], bulk and shear modulus [Pa].
std::unique_ptr<Material> make_linear_elastic(double rho, double K, double G);
std::unique_ptr<Material> make_neo_hookean(double rho, double K, double G);
}  // namespace mpmfrag

#include "mpm/materials/tillotson.hpp"
namespace mpmfrag {
/// Tillotson + elastic deviatoric with shear modulus G [Pa].
std::unique_ptr<Material> make_tillotson(const TillotsonParams& p, double G);
}  // namespace mpmfrag
