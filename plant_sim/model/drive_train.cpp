// Drive-train dynamics.
#include "drive_train.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace windfdi::plant {

void DriveTrain::step(const TurbineParams& p, double rotor_inertia, double eta, double t_aero, double tg,
                      double h) {
  const double n = p.gear_ratio, jr = rotor_inertia, jg = p.generator_inertia;
  const double kdt = p.drive_train_stiffness, bdt = p.drive_train_damping, br = p.rotor_friction,
               bg = p.generator_friction;
  // Witczak et al. eqs 31-33.
  auto f = [&](const std::array<double, 3>& x) {
    return std::array<double, 3>{
        -(bdt + br) / jr * x[0] + bdt / (n * jr) * x[1] - kdt / jr * x[2] + t_aero / jr,
        eta * bdt / (n * jg) * x[0] - (eta * bdt / (n * n * jg) + bg / jg) * x[1] +
            eta * kdt / (n * jg) * x[2] - tg / jg,
        x[0] - x[1] / n};
  };
  std::array<double, 3> x{rotor_speed, generator_speed, torsion};
  const auto k1 = f(x);
  std::array<double, 3> x2, x3, x4;
  for (int j = 0; j < 3; ++j) x2[j] = x[j] + 0.5 * h * k1[j];
  const auto k2 = f(x2);
  for (int j = 0; j < 3; ++j) x3[j] = x[j] + 0.5 * h * k2[j];
  const auto k3 = f(x3);
  for (int j = 0; j < 3; ++j) x4[j] = x[j] + h * k3[j];
  const auto k4 = f(x4);
  for (int j = 0; j < 3; ++j) x[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  rotor_speed = std::max(0.0, x[0]);
  generator_speed = std::max(0.0, x[1]);
  torsion = x[2];
}

}  // namespace windfdi::plant
