// Generalized coordinates of the SA model (docs/model.md §2):
// q = [x, y, z, theta, chi, psi, phi, b11, b12, b21, b22, b31, b32, b41, b42,
//      d1, d2, d3, d4, z1, z2, z3, z4], generalized speeds u = dq/dt.
#pragma once

#include <Eigen/Core>

namespace rover {

inline constexpr int kNumCoordinates = 23;
inline constexpr int kStateSize = 2 * kNumCoordinates;

using Coordinates = Eigen::Matrix<double, kNumCoordinates, 1>;
// Any 23 x 23 matrix over the coordinates: M, dF/du, dF/dq.
using CoordinateMatrix = Eigen::Matrix<double, kNumCoordinates, kNumCoordinates>;
using StateVector = Eigen::Matrix<double, kStateSize, 1>;

namespace coord {
inline constexpr int x = 0, y = 1, z = 2;
inline constexpr int yaw = 3, pitch = 4, roll = 5;  // theta, chi, psi
inline constexpr int bogie = 6;                     // phi (right bogie +phi, left -phi)
// S-structure joint i (0 = hip, 1 = knee) of leg j (0..3).
inline constexpr int s_joint(int leg, int i) { return 7 + 2 * leg + i; }
inline constexpr int steer(int leg) { return 15 + leg; }  // d_j
inline constexpr int spin(int leg) { return 19 + leg; }   // z_j (rolling angle)
}  // namespace coord

// Names in docs/model.md order, for files and messages.
inline constexpr const char* kCoordinateNames[kNumCoordinates] = {
    "x",   "y",   "z",   "theta", "chi", "psi", "phi", "b11", "b12", "b21", "b22", "b31",
    "b32", "b41", "b42", "d1",    "d2",  "d3",  "d4",  "z1",  "z2",  "z3",  "z4"};

}  // namespace rover
