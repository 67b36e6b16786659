// One RK4 step of the hydraulic pitch actuator, with its valve's rate limit and its end stops.
#include "pitch_actuator.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi {

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

}  // namespace windfdi
