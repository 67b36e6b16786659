// Discrete-time drive-train and pitch models of Witczak et al. (eqs 31-40), their bias-augmented forms, and
// discretisation.
#include "lti_models.hpp"

#include <unsupported/Eigen/MatrixFunctions>

namespace windfdi::sensor_bias {

void drive_train_continuous(const TurbineParams& p, double aero_damping, Eigen::MatrixXd& A,
                            Eigen::MatrixXd& B, Eigen::MatrixXd& C) {
  const double jr = p.rotor_inertia, jg = p.generator_inertia, n = p.gear_ratio, k = p.drive_train_stiffness,
               bdt = p.drive_train_damping, br = p.rotor_friction, bg = p.generator_friction,
               eta = p.drive_train_efficiency;
  A.resize(3, 3);
  // Witczak et al. eq 31 (plus the design-only aerodynamic damping), eq 32, eq 33.
  A << -(bdt + br + aero_damping) / jr, bdt / (n * jr), -k / jr,                        //
      eta * bdt / (n * jg), -(eta * bdt / (n * n * jg) + bg / jg), eta * k / (n * jg),  //
      1.0, -1.0 / n, 0.0;
  B.resize(3, 2);
  B << 1.0 / jr, 0.0, 0.0, -1.0 / jg, 0.0, 0.0;
  C.resize(2, 3);
  C << 1, 0, 0, 0, 1, 0;
}

void pitch_continuous(double omega_n, double zeta, Eigen::MatrixXd& A, Eigen::MatrixXd& B,
                      Eigen::MatrixXd& C) {
  // Eq 34 corrected: beta'' = -2 zeta omega_n beta' - omega_n^2 (beta - beta_ref).
  A.resize(2, 2);
  A << 0.0, 1.0, -omega_n * omega_n, -2.0 * zeta * omega_n;
  B.resize(2, 1);
  B << 0.0, omega_n * omega_n;
  C.resize(1, 2);
  C << 1.0, 0.0;
}

DiscreteModel discretise_zoh(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                             double T) {
  const Eigen::Index n = A.rows(), r = B.cols();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + r, n + r);
  M.topLeftCorner(n, n) = A * T;
  M.topRightCorner(n, r) = B * T;
  const Eigen::MatrixXd E = M.exp();
  return {E.topLeftCorner(n, n), E.topRightCorner(n, r), C, T};
}

DiscreteModel discretise_euler(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                               double T) {
  return {Eigen::MatrixXd::Identity(A.rows(), A.cols()) + A * T, B * T, C, T};
}

DiscreteModel paper_drive_train() {
  DiscreteModel m;
  m.A.resize(3, 3);
  m.A << 1.0000, 0.0000, -0.0005, 0.0002, 0.9988, 0.0191, 0.0100, -0.0001, 0.9900;  // eq 35
  m.B.resize(3, 2);
  m.B << 0.0, 0.0, 0.0, -0.2564e-4, 0.0, 0.0;  // eq 36
  m.C.resize(2, 3);
  m.C << 1, 0, 0, 0, 1, 0;  // eq 37
  return m;
}

DiscreteModel paper_pitch() {
  DiscreteModel m;
  m.A.resize(2, 2);
  m.A << 1.0000, 0.0100, -1.2343, 0.8667;  // eq 38
  m.B.resize(2, 1);
  m.B << 0.0, 1.2343;  // eq 39
  m.C.resize(1, 2);
  m.C << 1, 0;  // eq 40
  return m;
}

Eigen::MatrixXd paper_K_drive_train() {
  Eigen::MatrixXd K(3, 2);
  K << 0.5349, 0.0154, 0.0688, 0.3338, 0.2735, 0.0362;  // eq 43
  return K;
}

Eigen::MatrixXd paper_K_pitch() {
  Eigen::MatrixXd K(2, 1);
  K << 0.5839, -3.8104;  // eq 44
  return K;
}

DiscreteModel augment_with_output_biases(const DiscreteModel& m, BiasModel model) {
  const Eigen::Index n = m.A.rows(), p = m.C.rows(), r = m.B.cols();
  const Eigen::Index nr = model == BiasModel::kIntegratedRandomWalk ? p : 0;  // rate states
  DiscreteModel a;
  a.sample_time = m.sample_time;
  a.A = Eigen::MatrixXd::Identity(n + p + nr, n + p + nr);
  a.A.topLeftCorner(n, n) = m.A;
  if (nr > 0) a.A.block(n, n + p, p, p) = m.sample_time * Eigen::MatrixXd::Identity(p, p);  // b+ = b + T r
  a.B = Eigen::MatrixXd::Zero(n + p + nr, r);
  a.B.topRows(n) = m.B;
  a.C = Eigen::MatrixXd::Zero(p, n + p + nr);
  a.C.leftCols(n) = m.C;
  a.C.block(0, n, p, p).setIdentity();
  return a;
}

Observability observability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C) {
  Observability o;
  const Eigen::Index n = A.rows();
  o.n = static_cast<int>(n);
  Eigen::MatrixXd O(C.rows() * n, n);
  Eigen::MatrixXd Ak = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    O.middleRows(k * C.rows(), C.rows()) = C * Ak;
    Ak = Ak * A;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(O);
  svd.setThreshold(1e-12);
  o.rank = static_cast<int>(svd.rank());
  Eigen::EigenSolver<Eigen::MatrixXd> es(A);
  o.eigenvalues = es.eigenvalues();
  o.pbh_sigma_min.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::MatrixXcd M(n + C.rows(), n);
    M.topRows(n) = A.cast<std::complex<double>>() - o.eigenvalues(i) * Eigen::MatrixXcd::Identity(n, n);
    M.bottomRows(C.rows()) = C.cast<std::complex<double>>();
    Eigen::JacobiSVD<Eigen::MatrixXcd> s(M);
    o.pbh_sigma_min(i) = s.singularValues()(n - 1);
  }
  return o;
}

}  // namespace windfdi::sensor_bias
