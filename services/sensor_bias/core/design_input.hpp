// windfdi-qb-design's input (A, B, C, W1, W2, Qw from YAML, or the turbine model discretised) and gain files.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "lti_models.hpp"
#include "qb_design.hpp"
#include "yaml_config.hpp"

namespace windfdi::sensor_bias {

/// A design request as read from a design YAML (documented in services/sensor_bias/README.md).
struct DesignInput {
  std::string name;                   ///< free text, copied to the gain file
  std::string subsystem = "generic";  ///< drive_train, pitch or generic
  QbProblem problem;
  bool fixed_alpha = false;  ///< true: solve at `alpha` only; false: search alpha in (0, 1)
  double alpha = 0.0;        ///< (0, 1)
  AlphaSearch search;
  double sample_time = 0.01;        ///< s
  std::vector<std::string> states;  ///< state names (the gain file's and the service's check)
  double aero_damping =
      0.0;  ///< N m s/rad folded into A (drive train); the service adds k_a omega_r back to T_aero
};

/// Reads a design YAML. Matrices are lists of rows. Errors are ConfigErrors naming file, line and key.
DesignInput load_design_input(const YamlSection& s);
DesignInput load_design_input_file(const std::string& path);

/// A designed gain as the service loads it.
struct GainFile {
  std::string file;
  std::string name, subsystem, structure;  ///< structure: paper or observer
  double sample_time = 0.01, alpha = 0.0, trace = 0.0, lmi_max_eigenvalue = 0.0, closed_loop_radius = 0.0;
  std::vector<std::string> states;
  double aero_damping = 0.0;  ///< N m s/rad inside A: the runtime input is T_aero(omega_r) + k_a omega_r
  Eigen::MatrixXd A, B, C, K, P, R;
  Eigen::VectorXd state_bound, bias_bound;
};

/// Writes the gain file of a solved design (text YAML with a header comment).
std::string gain_file_text(const DesignInput& in, const QbSolution& sol, const std::string& source);
/// Loads a gain file; checks dimensions and finiteness, and that the gain's QB certificate is negative.
GainFile load_gain_file(const std::string& path);

/// Reads a matrix (list of rows) or a vector (list of numbers as a column); throws ConfigError on bad shape.
Eigen::MatrixXd yaml_matrix(const YamlSection& s, const std::string& key);

}  // namespace windfdi::sensor_bias
