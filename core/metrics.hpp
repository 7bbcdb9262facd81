// Metrics of docs/model.md §8: the deflection error (paper eq. 10), the
// at-rest error (eq. 11) and the RMS difference between two sampled curves.
#pragma once

#include <vector>

namespace rover {

// RMS of (b - a) over the common time interval, b linearly interpolated onto
// the sample times of a. Throws std::invalid_argument if the curves do not
// overlap or the times are not increasing.
double rms_difference(const std::vector<double>& t_a, const std::vector<double>& a,
                      const std::vector<double>& t_b, const std::vector<double>& b);

// Linear interpolation of (t, y) at time `at` (clamped to the ends). Throws
// std::invalid_argument for a curve without samples.
double interpolate(const std::vector<double>& t, const std::vector<double>& y, double at);

// eps_d = (z_r - z_min) / (z_r,ref - z_min,ref) - 1 with z_min = min over t of
// B_l z and z_r = B_l z at t = t_rest (1 s for the drop tests).
double deflection_error(const std::vector<double>& t, const std::vector<double>& z,
                        const std::vector<double>& t_ref, const std::vector<double>& z_ref,
                        double t_rest_s = 1.0);

// eps_r = z(t_rest) / z_ref(t_rest) - 1.
double at_rest_error(const std::vector<double>& t, const std::vector<double>& z,
                     const std::vector<double>& t_ref, const std::vector<double>& z_ref,
                     double t_rest_s = 1.0);

}  // namespace rover
