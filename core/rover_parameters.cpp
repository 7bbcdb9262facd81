// Defaults of docs/model.md §3–6 (see rover_parameters.hpp).
#include "core/rover_parameters.hpp"

namespace rover {

RoverParameters default_rover_parameters() {
  RoverParameters p;
  p.chassis.mass_kg = 1.267;
  p.chassis.inertia_kgm2 << 6.63e-3, 0, -1.5e-4, 0, 1.102e-2, 0, -1.5e-4, 0, 1.461e-2;
  p.bogie.mass_kg = 0.174;
  p.bogie.com_m = Vec3(0, 0, -0.0133);
  p.bogie.inertia_kgm2 = Vec3(1.1e-5, 6.84e-4, 6.74e-4).asDiagonal();
  p.module1.mass_kg = 0.079;
  p.module1.com_m = Vec3(0.0421, 0, -0.0270);
  p.module1.inertia_kgm2 << 2.4e-5, 0, 3.0e-5, 0, 7.0e-5, 0, 3.0e-5, 0, 5.0e-5;
  p.module2.mass_kg = 0.393;
  p.module2.com_m = Vec3(0.100, 0.040, -0.020);
  p.module2.inertia_kgm2 << 1.6e-4, 0, 1.8e-4, 0, 9.8e-4, 0, 1.8e-4, 0, 9.2e-4;
  p.wheel.mass_kg = 0.231;
  p.wheel.inertia_kgm2 = Vec3(4.48e-4, 8.345e-4, 4.48e-4).asDiagonal();
  return p;
}

}  // namespace rover
