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

/// The design `template_file` (a design YAML with a turbine `model:`, made for one turbine) made for the
/// turbine in `turbine_file`: the same sensors and noise bounds, and for a drive train its torque bounds
/// (`input_bound`: aerodynamic, generator) scaled by the two turbines' rated torques (P / omega_r and
/// P / omega_g) and its `aero_damping` by their rated aerodynamic torque per rotor speed, the rule by which
/// design_drive_train_observer_2MW.yaml was written by hand. A pitch design takes the file's actuator.
DesignInput design_for_turbine(const std::string& template_file, const std::string& turbine_file);

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
/// The same, of a gain file's text (`source` names it in errors).
GainFile parse_gain_file(const std::string& text, const std::string& source);
/// Whether `gain`'s model (drive train or pitch) is the one `turbine` gives: its discretised physical states'
/// A and B (the drive train with the gain's own aero_damping) within a relative 1e-6. A gain designed for
/// another turbine's inertias, stiffness or pitch actuator estimates that turbine's biases, not this one's.
bool gain_fits_turbine(const GainFile& gain, const TurbineParams& turbine);
/// `gain` if it fits `turbine`, the turbine of `turbine_file`; otherwise, with `design` allowed, a gain
/// designed now from `design_file` made for that turbine (design_for_turbine; `note` says so, with the
/// design's alpha and time), else a ConfigError naming `gain_key` and both files. Infeasible designs are
/// ConfigErrors too.
GainFile gain_for_turbine(const GainFile& gain, const std::string& gain_key, const std::string& design_file,
                          const std::string& turbine_file, const TurbineParams& turbine, bool design,
                          std::string& note);

/// Reads a matrix (list of rows) or a vector (list of numbers as a column); throws ConfigError on bad shape.
Eigen::MatrixXd yaml_matrix(const YamlSection& s, const std::string& key);

}  // namespace windfdi::sensor_bias
