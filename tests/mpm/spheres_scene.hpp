/// @file spheres_scene.hpp
/// Two elastic spheres colliding off-centre at 5 m/s each (soft material, 0.01 m cells): the
/// scene of the momentum/determinism tests and of the energy-budget test.
#pragma once

namespace mpmtest {

inline const char* kSpheres = R"(
[grid]
domain_min = [-0.3, -0.1, -0.1]
domain_max = [0.3, 0.1, 0.1]
cell_size = 0.01
[solver]
scheme = "musl"
courant = 0.3
min_mass_fraction = 0.0
[time]
end = 0.03
[[material]]
name = "soft"
model = "elastic"
density = 1000.0
bulk_modulus = 1.0e7
shear_modulus = 3.0e6
[[body]]
material = "soft"
shape = "sphere"
center = [-0.06, 0.003, 0.0]
radius = 0.05
velocity = [5.0, 0.0, 0.0]
[[body]]
material = "soft"
shape = "sphere"
center = [0.06, -0.003, 0.0]
radius = 0.05
velocity = [-5.0, 0.0, 0.0]
)";

}  // namespace mpmtest
