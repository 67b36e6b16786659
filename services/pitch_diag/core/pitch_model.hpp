// Second-order pitch-actuator model of Wu & Li (MIFG pitch diagnosis): exact ZOH theta <->
// (omega_n, zeta) and classification against the Table 1 fault signatures along the fault paths of eqs 11-13.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace windfdi::pitch_diag {

/// Discrete model y(t) = -a1 y(t-1) - a2 y(t-2) + b1 u(t-1) + b2 u(t-2): theta = [a1, a2, b1, b2] (eq 10 with
/// the b2 term of the exact ZOH discretisation; docs/papers.md, Wu & Li).
using Theta = Eigen::Vector4d;

/// The continuous actuator beta/beta_ref = omega_n^2 / (s^2 + 2 zeta omega_n s + omega_n^2) (eq 6).
struct ContinuousModel {
  double omega_n = 0.0;  ///< rad/s
  double zeta = 0.0;     ///< damping ratio (>= 1: real pole pair)
  double gain = 0.0;     ///< DC gain (b1 + b2) / (1 + a1 + a2), 1 for an ideal position servo
  bool valid = false;    ///< false: a pole outside (0, 1) (unstable, oscillating at Nyquist or non-physical)
};

/// Exact zero-order-hold discretisation of eq 6 with unit DC gain (replaces eqs 7-9, which miss a factor T
/// and define the roots a, b wrongly). Valid for every zeta > 0, including a real pole pair (zeta >= 1).
Theta theta_from_continuous(double omega_n, double zeta, double T);

/// Inverse mapping through the discrete poles z = exp(s T), s = -zeta omega_n +- j omega_n sqrt(1 - zeta^2).
ContinuousModel continuous_from_theta(const Theta& theta, double T);

/// Jury test for z^2 + a1 z + a2: both poles strictly inside the unit circle.
inline bool is_stable(const Theta& theta) {
  return std::abs(theta(1)) < 1.0 && std::abs(theta(0)) < 1.0 + theta(1);
}

/// One row of Table 1: the healthy actuator (name "none") or a fully developed fault (alpha = 1).
struct Signature {
  std::string name;  ///< "none" or a canonical pitch fault class
  double omega_n;    ///< rad/s
  double zeta;
};

/// Table 1 of the paper: none, pump_wear, hydraulic_leakage, high_air_content.
std::vector<Signature> table1_signatures();

/// How (omega_n, zeta) are weighed against the fault paths.
struct ClassifierConfig {
  std::vector<Signature> signatures = table1_signatures();  ///< [0] is the healthy actuator
  double omega_scale = 1.0;       ///< rad/s of omega_n that weigh as much as zeta_scale
  double zeta_scale = 0.05;       ///< damping-ratio difference weighed as omega_scale
  double alpha_detect = 0.25;     ///< alpha below which the blade is "none"
  double ambiguity_margin = 0.5;  ///< normalised distance within which two paths explain the point equally
  double max_distance = 3.0;      ///< normalised distance beyond which no path fits (reported, not hidden)
};

/// The point (omega_n, zeta) projected onto every fault path h + alpha (f - h) of eqs 11-13.
struct Classification {
  std::string fault_class = "none";  ///< canonical class of the best path, "none" below alpha_detect
  double alpha = 0.0;                ///< fault indicator along that path (eqs 11-13), 0 healthy .. 1 full
  double raw_alpha = 0.0;            ///< alpha along the best path even below alpha_detect (progress)
  double distance = 0.0;             ///< normalised distance from that path
  double excursion = 0.0;            ///< normalised distance of the point from the healthy actuator
  bool ambiguous = false;  ///< a second path explains the point as well (e.g. pump wear vs half leakage)
  std::string alt_class;   ///< that second path, when ambiguous
  double alt_alpha = 0.0;  ///< its alpha
  bool fits = true;        ///< false: no path within max_distance (dynamics unlike any Table 1 fault)
  std::vector<double> path_alpha;     ///< alpha along each fault path (signatures[1..]), clamped to [0, 1.5]
  std::vector<double> path_distance;  ///< normalised distance from each fault path
};

/// Least-squares projection of (omega_n, zeta) on each path (eqs 11-13 solved for alpha).
Classification classify(double omega_n, double zeta, const ClassifierConfig& config);
/// The same into `out`, reusing its storage: no allocation once it has held a classification.
void classify(double omega_n, double zeta, const ClassifierConfig& config, Classification& out);

}  // namespace windfdi::pitch_diag
