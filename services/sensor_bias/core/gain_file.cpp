// Gain files of windfdi-qb-design: writing a solved design, loading it for the sensor_bias service.
#include <cstdio>
#include <sstream>

#include "csv.hpp"
#include "design_input.hpp"
#include "lti_models.hpp"

namespace windfdi::sensor_bias {

namespace {

std::string row_text(const Eigen::RowVectorXd& r) {
  std::string s = "[";
  for (Eigen::Index j = 0; j < r.size(); ++j) s += (j ? ", " : "") + format_number(r(j));
  return s + "]";
}

void write_matrix(std::ostringstream& o, const char* key, const Eigen::MatrixXd& M) {
  o << key << ":\n";
  for (Eigen::Index i = 0; i < M.rows(); ++i) o << "  - " << row_text(M.row(i)) << "\n";
}

}  // namespace

std::string gain_file_text(const DesignInput& in, const QbSolution& sol, const std::string& source) {
  std::ostringstream o;
  o << "# Observer gain from windfdi-qb-design (Witczak et al. quadratic boundedness, K = P^-1 U, eq 30).\n";
  o << "# Design input: " << source << ". Do not edit by hand: re-run the design.\n";
  o << "name: " << in.name << "\n";
  o << "subsystem: " << in.subsystem << "\n";
  o << "structure: " << (in.problem.structure == QbStructure::kPaper ? "paper" : "observer") << "\n";
  o << "sample_time: " << format_number(in.sample_time) << "    # s\n";
  o << "alpha: " << format_number(sol.alpha) << "\n";
  o << "aero_damping: " << format_number(in.aero_damping)
    << "    # N m s/rad in A; input is T_aero + k_a omega_r\n";
  o << "trace: " << format_number(sol.trace) << "    # tr(P) (+ tr(R)): larger = smaller invariant set\n";
  o << "lmi_max_eigenvalue: " << format_number(sol.lmi_max_eigenvalue)
    << "    # independent check, must be < 0\n";
  o << "closed_loop_radius: " << format_number(sol.closed_loop_radius) << "\n";
  o << "states: [";
  for (std::size_t i = 0; i < in.states.size(); ++i) o << (i ? ", " : "") << in.states[i];
  o << "]\n";
  if (sol.state_bound.size())
    o << "state_bound: " << row_text(sol.state_bound.transpose()) << "    # max |e_i| on the invariant set\n";
  if (sol.bias_bound.size())
    o << "bias_bound: " << row_text(sol.bias_bound.transpose())
      << "    # per output, bias-estimation error bound\n";
  write_matrix(o, "A", in.problem.A);
  write_matrix(o, "B", in.problem.B);
  write_matrix(o, "C", in.problem.C);
  write_matrix(o, "K", sol.K);
  write_matrix(o, "P", sol.P);
  if (sol.R.size()) write_matrix(o, "R", sol.R);
  return o.str();
}

namespace {

GainFile gain_file_from(const YamlSection& s, const std::string& path) {
  s.require_known_keys({"name", "subsystem", "structure", "sample_time", "alpha", "trace",
                        "lmi_max_eigenvalue", "closed_loop_radius", "aero_damping", "states", "state_bound",
                        "bias_bound", "A", "B", "C", "K", "P", "R"});
  GainFile g;
  g.file = path;
  g.name = s.get<std::string>("name", "");
  g.subsystem = s.get_choice("subsystem", "generic", {"drive_train", "pitch", "generic"});
  g.structure = s.get_choice("structure", "observer", {"paper", "observer"});
  g.sample_time = s.require_number("sample_time", 1e-5, 10.0);
  g.alpha = s.require_number("alpha", 0.0, 1.0);
  g.trace = s.get_number("trace", 0.0, 0.0, 1e300);
  g.lmi_max_eigenvalue = s.get_number("lmi_max_eigenvalue", 1.0, -1e300, 1e300);
  g.closed_loop_radius = s.get_number("closed_loop_radius", 0.0, 0.0, 1e6);
  g.aero_damping = s.get_number("aero_damping", 0.0, 0.0, 1e9);
  g.states = s.get<std::vector<std::string>>("states", {});
  g.A = yaml_matrix(s, "A");
  g.B = yaml_matrix(s, "B");
  g.C = yaml_matrix(s, "C");
  g.K = yaml_matrix(s, "K");
  if (s.has("P")) g.P = yaml_matrix(s, "P");
  if (s.has("R")) g.R = yaml_matrix(s, "R");
  if (s.has("state_bound")) g.state_bound = yaml_matrix(s, "state_bound");
  if (s.has("bias_bound")) g.bias_bound = yaml_matrix(s, "bias_bound");
  const auto n = g.A.rows();
  if (g.A.cols() != n) throw s.error("A", "must be square");
  if (g.B.rows() != n) throw s.error("B", "must have as many rows as A");
  if (g.C.cols() != n) throw s.error("C", "must have as many columns as A");
  if (g.K.rows() != n || g.K.cols() != g.C.rows()) throw s.error("K", "must be (states) x (outputs)");
  // An observer gain must carry its QB certificate; a paper-mode gain need not (K only shapes a transient
  // there).
  if (g.structure == "observer" && !(g.lmi_max_eigenvalue < 0.0))
    throw s.error("lmi_max_eigenvalue", "the design is not certified (must be < 0)");
  if (!g.states.empty() && static_cast<Eigen::Index>(g.states.size()) != n)
    throw s.error("states", "must name every state of A");
  return g;
}

}  // namespace

GainFile load_gain_file(const std::string& path) {
  return gain_file_from(YamlSection::load_file(path), path);
}

GainFile parse_gain_file(const std::string& text, const std::string& source) {
  return gain_file_from(YamlSection(YAML::Load(text), source), source);
}

bool gain_fits_turbine(const GainFile& gain, const TurbineParams& turbine) {
  Eigen::MatrixXd Ac, Bc, Cc;
  if (gain.subsystem == "drive_train")
    drive_train_continuous(turbine, gain.aero_damping, Ac, Bc, Cc);
  else if (gain.subsystem == "pitch")
    pitch_continuous(turbine.pitch_omega_n, turbine.pitch_zeta, Ac, Bc, Cc);
  else
    return true;  // a generic model names no turbine
  const DiscreteModel d = discretise_zoh(Ac, Bc, Cc, gain.sample_time);
  const Eigen::Index n = d.A.rows(), m = d.B.cols();
  if (gain.A.rows() < n || gain.B.rows() < n || gain.B.cols() != m) return false;
  const auto close = [](const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
    return (x - y).norm() <= 1e-6 * y.norm();
  };
  return close(gain.A.topLeftCorner(n, n), d.A) && close(gain.B.topRows(n), d.B);
}

Eigen::MatrixXd yaml_matrix(const YamlSection& s, const std::string& key) {
  if (!s.has(key)) throw s.error(key, "required matrix is missing");
  const YAML::Node n = s.node()[key];
  if (!n.IsSequence() || n.size() == 0)
    throw s.error(key, "must be a non-empty list of rows (or of numbers)");
  try {
    if (!n[0].IsSequence()) {
      Eigen::MatrixXd v(n.size(), 1);
      for (std::size_t i = 0; i < n.size(); ++i) v(static_cast<Eigen::Index>(i), 0) = n[i].as<double>();
      if (!v.allFinite()) throw s.error(key, "holds NaN or Inf");
      return v;
    }
    const std::size_t cols = n[0].size();
    Eigen::MatrixXd M(n.size(), cols);
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsSequence() || n[i].size() != cols)
        throw ConfigError(s.file(), n[i].Mark().line + 1, s.key_path(key),
                          "row " + std::to_string(i) + " has " + std::to_string(n[i].size()) +
                              " entries, expected " + std::to_string(cols));
      for (std::size_t j = 0; j < cols; ++j)
        M(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = n[i][j].as<double>();
    }
    if (!M.allFinite()) throw s.error(key, "holds NaN or Inf");
    return M;
  } catch (const YAML::Exception&) {
    throw s.error(key, "entries must be numbers");
  }
}

}  // namespace windfdi::sensor_bias
