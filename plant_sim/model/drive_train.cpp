// Drive-train and pitch-actuator dynamics.
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

void PitchActuator::step(double ref, double h, double wn, double zeta, double limit, double lo, double hi) {
  const double w2 = wn * wn, c = 2.0 * zeta * wn;
  auto acc = [&](double be, double ra) { return -c * ra - w2 * (be - ref); };
  const double b0 = angle, r0 = rate;
  const double k1b = r0, k1r = acc(b0, r0);
  const double k2b = r0 + 0.5 * h * k1r, k2r = acc(b0 + 0.5 * h * k1b, k2b);
  const double k3b = r0 + 0.5 * h * k2r, k3r = acc(b0 + 0.5 * h * k2b, k3b);
  const double k4b = r0 + h * k3r, k4r = acc(b0 + h * k3b, k4b);
  double b_new = b0 + h / 6.0 * (k1b + 2 * k2b + 2 * k3b + k4b);
  double r_new = r0 + h / 6.0 * (k1r + 2 * k2r + 2 * k3r + k4r);
  if (std::fabs(r_new) > limit) {
    // The valve saturates: the angle moves at the rate limit.
    r_new = std::clamp(r_new, -limit, limit);
    b_new = b0 + 0.5 * h * (r0 + r_new);
  }
  if (b_new < lo || b_new > hi) {
    b_new = std::clamp(b_new, lo, hi);
    r_new = 0.0;
  }
  angle = b_new;
  rate = r_new;
}

}  // namespace windfdi::plant
