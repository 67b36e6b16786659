// Discrete-time drive-train and pitch models of Witczak et al. (eqs 31-40), their bias-augmented forms, and
// discretisation.
#pragma once

#include <Eigen/Dense>
#include <string>

#include "turbine_params.hpp"

namespace windfdi::sensor_bias {

/// A discrete-time linear system x+ = A x + B u, y = C x (the disturbance maps W1, W2 belong to the design).
struct DiscreteModel {
  Eigen::MatrixXd A, B, C;
  double sample_time = 0.01;  ///< s
};

/// Continuous-time drive train of Witczak et al. eqs 31-33: x = [omega_r, omega_g, theta_delta], u = [T_aero,
/// T_g], y = [omega_r, omega_g]. `aero_damping` (N m s/rad, >= 0) adds -k_a omega_r / J_r to eq 31: the
/// linearised dependence of the aerodynamic torque on rotor speed, used only for the gain design (see
/// README).
void drive_train_continuous(const TurbineParams& p, double aero_damping, Eigen::MatrixXd& A,
                            Eigen::MatrixXd& B, Eigen::MatrixXd& C);
/// Continuous-time pitch actuator, eq 34 with the -omega_n^2 beta term it lacks (docs/papers.md, Witczak et
/// al.): x = [beta, beta_dot], u = beta_ref, y = beta (deg).
void pitch_continuous(double omega_n, double zeta, Eigen::MatrixXd& A, Eigen::MatrixXd& B,
                      Eigen::MatrixXd& C);

/// Exact zero-order-hold discretisation: exp([[A, B], [0, 0]] T).
DiscreteModel discretise_zoh(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                             double T);
/// Forward Euler: I + A T, B T (what the paper used; unstable for the drive train's torsional mode at 0.01
/// s).
DiscreteModel discretise_euler(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                               double T);

/// The paper's printed matrices and gains: eqs 35-37 (drive train), 38-40 (pitch), 43-44 (gains).
DiscreteModel paper_drive_train();
DiscreteModel paper_pitch();
Eigen::MatrixXd paper_K_drive_train();
Eigen::MatrixXd paper_K_pitch();

/// How a sensor bias evolves between samples in the augmented model.
enum class BiasModel {
  kRandomWalk,  ///< b+ = b + w_b: constant between kicks; a ramp or slow sinusoid is followed with a lag
  kIntegratedRandomWalk,  ///< b+ = b + T r + w_b, r+ = r + w_r: a rate state, so a ramp is followed without
                          ///< lag
};

/// Augments a model with one sensor bias per output:
///   random walk:            z = [x; b],    A_a = [[A, 0], [0, I]],                  C_a = [C, I]
///   integrated random walk: z = [x; b; r], A_a = [[A, 0, 0], [0, I, T I], [0, 0, I]], C_a = [C, I, 0]
/// with B_a = [B; 0]. The bias states keep their indices in both forms (the rates are appended).
DiscreteModel augment_with_output_biases(const DiscreteModel& m, BiasModel model = BiasModel::kRandomWalk);

/// Rank of the observability matrix of (A, C) and the smallest singular value of the PBH matrix [A - lambda
/// I; C] over the eigenvalues lambda of A (after scaling the states by `scale`): 0 = unobservable mode.
struct Observability {
  int rank = 0;
  int n = 0;
  Eigen::VectorXd pbh_sigma_min;  ///< per eigenvalue of A (in the order of eigenvalues())
  Eigen::VectorXcd eigenvalues;
};
Observability observability(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C);

}  // namespace windfdi::sensor_bias
