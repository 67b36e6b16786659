// Wu & Li: exact ZOH mapping of the second-order pitch actuator and the fault-path classifier.
#include "pitch_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace windfdi::pitch_diag {

namespace {

// exp(-sigma t) * c(t) and exp(-sigma t) * sn(t) with c = cos(wd t), sn = sin(wd t) / wd (zeta < 1),
// cosh / sinh (zeta > 1), 1 / t (zeta = 1): one formula for every damping, without 0/0 near zeta = 1.
void modes(double omega_n, double zeta, double t, double& ec, double& esn) {
  const double sigma = zeta * omega_n;
  const double d = omega_n * omega_n * (1.0 - zeta * zeta);  // wd^2 (negative for a real pole pair)
  double c, sn;
  const double w = std::sqrt(std::abs(d));
  if (w * t < 1e-6) {
    c = 1.0;
    sn = t;
  } else if (d > 0.0) {
    c = std::cos(w * t);
    sn = std::sin(w * t) / w;
  } else {
    c = std::cosh(w * t);
    sn = std::sinh(w * t) / w;
  }
  const double e = std::exp(-sigma * t);
  ec = e * c;
  esn = e * sn;
}

}  // namespace

Theta theta_from_continuous(double omega_n, double zeta, double T) {
  // Poles z1,2 = exp(s1,2 T): a1 = -(z1 + z2) = -2 e^{-sigma T} c(T), a2 = z1 z2 = e^{-2 sigma T}.
  double ec1, esn1, ec2, esn2;
  modes(omega_n, zeta, T, ec1, esn1);
  modes(omega_n, zeta, 2.0 * T, ec2, esn2);
  const double sigma = zeta * omega_n;
  Theta theta;
  theta(0) = -2.0 * ec1;
  theta(1) = std::exp(-2.0 * sigma * T);
  // Unit step response s(t) = 1 - e^{-sigma t} (c + sigma sn); the difference equation started at rest gives
  // y(1) = b1 and y(2) = -a1 b1 + b1 + b2.
  const double s1 = 1.0 - (ec1 + sigma * esn1);
  const double s2 = 1.0 - (ec2 + sigma * esn2);
  theta(2) = s1;
  theta(3) = s2 - s1 + theta(0) * s1;
  return theta;
}

ContinuousModel continuous_from_theta(const Theta& theta, double T) {
  ContinuousModel m;
  const double a1 = theta(0), a2 = theta(1);
  const double den = 1.0 + a1 + a2;
  m.gain = std::abs(den) > 1e-15 ? (theta(2) + theta(3)) / den : std::numeric_limits<double>::infinity();
  if (!(a2 > 0.0) || !(a2 < 1.0)) return m;  // pole product e^{-2 sigma T} must lie in (0, 1)
  const double disc = a1 * a1 - 4.0 * a2;
  if (disc < 0.0) {
    // Complex pair z = r e^{+-j wd T}: r^2 = a2, cos(wd T) = -a1 / (2 r).
    const double r = std::sqrt(a2);
    const double c = -a1 / (2.0 * r);
    if (c <= -1.0 || c >= 1.0) return m;
    const double sigma = -std::log(r) / T;
    const double wd = std::acos(c) / T;
    m.omega_n = std::sqrt(sigma * sigma + wd * wd);
    m.zeta = sigma / m.omega_n;
    m.valid = true;
    return m;
  }
  // Real pair (zeta >= 1): both poles must be in (0, 1) to come from s = ln(z) / T < 0.
  const double q = std::sqrt(disc);
  const double z1 = 0.5 * (-a1 + q), z2 = 0.5 * (-a1 - q);
  if (!(z2 > 0.0) || !(z1 < 1.0)) return m;
  const double s1 = std::log(z1) / T, s2 = std::log(z2) / T;
  m.omega_n = std::sqrt(s1 * s2);
  m.zeta = -(s1 + s2) / (2.0 * m.omega_n);
  m.valid = true;
  return m;
}

std::vector<Signature> table1_signatures() {
  return {{"none", 11.11, 0.6},
          {"pump_wear", 7.27, 0.75},
          {"hydraulic_leakage", 3.42, 0.9},
          {"high_air_content", 5.73, 0.45}};
}

void classify(double omega_n, double zeta, const ClassifierConfig& config, Classification& out) {
  // Every field set again, the path vectors and class names in the storage they have (10 Hz per blade).
  out.fault_class = "none";
  out.alpha = out.raw_alpha = out.distance = out.excursion = out.alt_alpha = 0.0;
  out.ambiguous = false;
  out.alt_class.clear();
  out.fits = true;
  const auto& sig = config.signatures;
  const std::size_t n_paths = sig.size() - 1;
  out.path_alpha.assign(n_paths, 0.0);
  out.path_distance.assign(n_paths, std::numeric_limits<double>::infinity());
  // Normalised coordinates so that omega_n (rad/s) and zeta (1) are comparable.
  const double px = (omega_n - sig[0].omega_n) / config.omega_scale;
  const double py = (zeta - sig[0].zeta) / config.zeta_scale;
  out.excursion = std::hypot(px, py);
  int best = -1, second = -1;
  for (std::size_t k = 0; k < n_paths; ++k) {
    // Eqs 11-13: (omega_n, zeta) = h + alpha (f - h); least-squares alpha, clamped to the physical range.
    const double dx = (sig[k + 1].omega_n - sig[0].omega_n) / config.omega_scale;
    const double dy = (sig[k + 1].zeta - sig[0].zeta) / config.zeta_scale;
    const double dd = dx * dx + dy * dy;
    double alpha = dd > 0.0 ? (px * dx + py * dy) / dd : 0.0;
    alpha = std::clamp(alpha, 0.0, 1.5);
    out.path_alpha[k] = alpha;
    out.path_distance[k] = std::hypot(px - alpha * dx, py - alpha * dy);
    if (best < 0 || out.path_distance[k] < out.path_distance[best]) {
      second = best;
      best = static_cast<int>(k);
    } else if (second < 0 || out.path_distance[k] < out.path_distance[second]) {
      second = static_cast<int>(k);
    }
  }
  if (best < 0) return;
  out.alpha = out.path_alpha[best];
  out.raw_alpha = out.alpha;
  out.distance = out.path_distance[best];
  out.fits = out.distance <= config.max_distance;
  if (out.alpha < config.alpha_detect) {
    out.alpha = 0.0;
    out.fault_class = "none";
    return;
  }
  out.fault_class = sig[best + 1].name;
  // A second path through the same point explains it as well, however small its alpha (pump wear at alpha_pw
  // is hydraulic leakage at about alpha_pw / 2).
  if (second >= 0 && out.path_distance[second] - out.distance < config.ambiguity_margin &&
      out.path_alpha[second] > 0.0) {
    out.ambiguous = true;
    out.alt_class = sig[second + 1].name;
    out.alt_alpha = out.path_alpha[second];
  }
}

Classification classify(double omega_n, double zeta, const ClassifierConfig& config) {
  Classification out;
  classify(omega_n, zeta, config, out);
  return out;
}

}  // namespace windfdi::pitch_diag
