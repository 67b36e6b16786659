// windfdi-qb-design's input: explicit matrices, or the turbine's drive train / pitch model discretised.
#include "design_input.hpp"

#include <cstdio>
#include <filesystem>
#include <vector>

namespace windfdi::sensor_bias {

namespace {

Eigen::VectorXd vector_or(const YamlSection& s, const std::string& key, Eigen::Index n, double fallback) {
  if (!s.has(key)) return Eigen::VectorXd::Constant(n, fallback);
  Eigen::MatrixXd v = yaml_matrix(s, key);
  if (v.cols() != 1 || v.rows() != n)
    throw s.error(key, "must be a list of " + std::to_string(n) + " numbers");
  if ((v.array() < 0.0).any()) throw s.error(key, "entries must be >= 0");
  return v.col(0);
}

// Builds A, B, C (augmented with output biases when asked) and W1, W2 from per-channel bounds.
void model_from_turbine(const YamlSection& m, DesignInput& in) {
  m.require_known_keys({"turbine_file", "subsystem", "sample_time", "discretisation", "aero_damping",
                        "augment_biases", "input_bound", "process_bound", "bias_rate_bound",
                        "measurement_bound", "omega_n", "zeta", "generator_speed_witness", "bias_model",
                        "bias_acceleration_bound"});
  m.require<std::string>("turbine_file");  // names file and key when it is missing
  const TurbineParams p = load_turbine_params_file(m.get_path("turbine_file", ""));
  in.subsystem = m.get_choice("subsystem", "drive_train", {"drive_train", "pitch"});
  in.sample_time = m.get_number("sample_time", 0.01, 1e-4, 1.0);
  const std::string disc = m.get_choice("discretisation", "zoh", {"zoh", "euler"});
  Eigen::MatrixXd Ac, Bc, Cc;
  if (in.subsystem == "drive_train") {
    in.aero_damping = m.get_number("aero_damping", 0.0, 0.0, 1e9);
    drive_train_continuous(p, in.aero_damping, Ac, Bc, Cc);
    in.states = {"omega_r", "omega_g", "theta_delta"};
  } else {
    pitch_continuous(m.get_number("omega_n", p.pitch_omega_n, 0.1, 100.0),
                     m.get_number("zeta", p.pitch_zeta, 0.01, 5.0), Ac, Bc, Cc);
    in.states = {"beta", "beta_dot"};
  }
  DiscreteModel d = disc == "zoh" ? discretise_zoh(Ac, Bc, Cc, in.sample_time)
                                  : discretise_euler(Ac, Bc, Cc, in.sample_time);
  const Eigen::Index n = d.A.rows(), r = d.B.cols(), mb_out = d.C.rows();  // mb_out: the biased sensors
  const bool augment = m.get<bool>("augment_biases", false);
  // bias_model: random_walk (b+ = b + w) or integrated_random_walk (a rate state r per bias: b+ = b + T r +
  // w, r+ = r + w_r), which follows a ramp without lag and a slow sinusoid with a lag of second order in its
  // frequency.
  const BiasModel bias_model =
      m.get_choice("bias_model", "random_walk", {"random_walk", "integrated_random_walk"}) ==
              "integrated_random_walk"
          ? BiasModel::kIntegratedRandomWalk
          : BiasModel::kRandomWalk;
  if (bias_model == BiasModel::kIntegratedRandomWalk && !augment)
    throw m.error("bias_model", "integrated_random_walk needs augment_biases: true");
  if (m.has("bias_acceleration_bound") && bias_model != BiasModel::kIntegratedRandomWalk)
    throw m.error("bias_acceleration_bound", "only with bias_model: integrated_random_walk");
  const bool rates = bias_model == BiasModel::kIntegratedRandomWalk;
  // generator_speed_witness: a third, bias-free output omega_g = P / (eta_g T_g) from the measured electrical
  // power and generator torque; it makes the common mode of the two speed-sensor biases observable.
  const bool witness = m.get<bool>("generator_speed_witness", false);
  if (witness && in.subsystem != "drive_train")
    throw m.error("generator_speed_witness", "only for subsystem drive_train");
  const Eigen::Index mo = mb_out + (witness ? 1 : 0);
  const Eigen::VectorXd ib = vector_or(m, "input_bound", r, 0.0), pb = vector_or(m, "process_bound", n, 0.0),
                        rb = vector_or(m, "bias_rate_bound", mb_out, 0.0),
                        mb = vector_or(m, "measurement_bound", mo, 0.0),
                        ab = vector_or(m, "bias_acceleration_bound", mb_out,
                                       0.0);  // per sample, on the rate state
  if (augment) {
    const std::vector<std::string> outs = in.subsystem == "drive_train"
                                              ? std::vector<std::string>{"bias_omega_r", "bias_omega_g"}
                                              : std::vector<std::string>{"bias_beta"};
    in.states.insert(in.states.end(), outs.begin(), outs.end());
    if (rates)
      for (const auto& o : outs) in.states.push_back("rate_" + o);
    d = augment_with_output_biases(d, bias_model);
  }
  if (witness) {
    Eigen::MatrixXd C(mo, d.A.cols());
    C.topRows(mb_out) = d.C;
    C.row(mb_out).setZero();
    C(mb_out, 1) = 1.0;  // the true generator speed
    d.C = C;
  }
  const Eigen::Index na = d.A.rows();
  // Disturbance columns: input errors (through B), process noise per physical state, bias rates, measurement
  // noise.
  std::vector<Eigen::VectorXd> c1, c2;
  for (Eigen::Index j = 0; j < r; ++j)
    if (ib(j) > 0) c1.push_back(d.B.col(j) * ib(j)), c2.push_back(Eigen::VectorXd::Zero(mo));
  for (Eigen::Index j = 0; j < n; ++j)
    if (pb(j) > 0)
      c1.push_back(Eigen::VectorXd::Unit(na, j) * pb(j)), c2.push_back(Eigen::VectorXd::Zero(mo));
  if (augment)
    for (Eigen::Index j = 0; j < mb_out; ++j)
      if (rb(j) > 0)
        c1.push_back(Eigen::VectorXd::Unit(na, n + j) * rb(j)), c2.push_back(Eigen::VectorXd::Zero(mo));
  if (rates)
    for (Eigen::Index j = 0; j < mb_out; ++j)
      if (ab(j) > 0)
        c1.push_back(Eigen::VectorXd::Unit(na, n + mb_out + j) * ab(j)),
            c2.push_back(Eigen::VectorXd::Zero(mo));
  for (Eigen::Index j = 0; j < mo; ++j)
    if (mb(j) > 0)
      c1.push_back(Eigen::VectorXd::Zero(na)), c2.push_back(Eigen::VectorXd::Unit(mo, j) * mb(j));
  if (c1.empty())
    throw m.error("",
                  "no disturbance: give input_bound, process_bound, bias_rate_bound or measurement_bound");
  in.problem.A = d.A;
  in.problem.B = d.B;
  in.problem.C = d.C;
  in.problem.W1.resize(na, static_cast<Eigen::Index>(c1.size()));
  in.problem.W2.resize(mo, static_cast<Eigen::Index>(c1.size()));
  for (std::size_t j = 0; j < c1.size(); ++j) {
    in.problem.W1.col(static_cast<Eigen::Index>(j)) = c1[j];
    in.problem.W2.col(static_cast<Eigen::Index>(j)) = c2[j];
  }
  in.problem.Qw = Eigen::MatrixXd::Identity(in.problem.W1.cols(), in.problem.W1.cols());
}

}  // namespace

DesignInput load_design_input(const YamlSection& s) {
  s.require_known_keys({"name", "structure", "objective", "alpha", "alpha_search", "model", "A", "B", "C",
                        "W1", "W2", "Qw", "state_scale", "states", "sample_time", "subsystem"});
  DesignInput in;
  in.name = s.get<std::string>("name", "design");
  in.problem.structure = s.get_choice("structure", "observer", {"paper", "observer"}) == "paper"
                             ? QbStructure::kPaper
                             : QbStructure::kObserver;
  const std::string objective = s.get_choice("objective", "trace", {"trace", "margin", "feasibility"});
  in.problem.objective = objective == "trace"    ? QbObjective::kTrace
                         : objective == "margin" ? QbObjective::kMargin
                                                 : QbObjective::kFeasibility;
  if (s.has("alpha")) {
    in.fixed_alpha = true;
    in.alpha = s.require_number("alpha", 1e-12, 1.0 - 1e-12);
  }
  const YamlSection a = s.section("alpha_search");
  a.require_known_keys({"min", "max", "grid", "refine", "bias_bound_ratio"});
  in.search.min = a.get_number("min", in.search.min, 1e-12, 0.999999);
  in.search.max = a.get_number("max", in.search.max, in.search.min, 0.999999);
  in.search.grid = static_cast<int>(a.get_number("grid", in.search.grid, 2, 1000));
  in.search.refine = static_cast<int>(a.get_number("refine", in.search.refine, 0, 100));
  in.search.bias_bound_ratio = a.get_number("bias_bound_ratio", in.search.bias_bound_ratio, 0.0, 1e6);
  if (s.has("model")) {
    for (const char* k : {"A", "B", "C", "W1", "W2"})
      if (s.has(k)) throw s.error(k, "give either 'model' or explicit matrices, not both");
    model_from_turbine(s.section("model"), in);
  } else {
    in.subsystem = s.get_choice("subsystem", "generic", {"drive_train", "pitch", "generic"});
    in.sample_time = s.get_number("sample_time", 0.01, 1e-6, 100.0);
    in.problem.A = yaml_matrix(s, "A");
    in.problem.B = yaml_matrix(s, "B");
    in.problem.C = yaml_matrix(s, "C");
    in.problem.W1 = yaml_matrix(s, "W1");
    in.problem.W2 =
        s.has("W2") ? yaml_matrix(s, "W2") : Eigen::MatrixXd::Zero(in.problem.C.rows(), in.problem.W1.cols());
    in.states = s.get<std::vector<std::string>>("states", {});
  }
  in.problem.Qw = s.has("Qw") ? yaml_matrix(s, "Qw")
                              : Eigen::MatrixXd::Identity(in.problem.W1.cols(), in.problem.W1.cols());
  if (s.has("state_scale")) in.problem.state_scale = yaml_matrix(s, "state_scale").col(0);
  if (in.states.empty())
    for (Eigen::Index i = 0; i < in.problem.A.rows(); ++i) in.states.push_back("x" + std::to_string(i + 1));
  const std::string why = check_problem(in.problem);
  if (!why.empty()) throw s.error("", "ill-posed design: " + why);
  if (static_cast<Eigen::Index>(in.states.size()) != in.problem.A.rows())
    throw s.error("states", "must name every state");
  return in;
}

DesignInput load_design_input_file(const std::string& path) {
  return load_design_input(YamlSection::load_file(path));
}

DesignInput design_for_turbine(const std::string& template_file, const std::string& turbine_file) {
  const YamlSection shipped = YamlSection::load_file(template_file);
  const YamlSection model = shipped.section("model");
  model.require<std::string>("turbine_file");
  const TurbineParams from = load_turbine_params_file(model.get_path("turbine_file", ""));
  const TurbineParams to = load_turbine_params_file(turbine_file);
  YAML::Node node = YAML::Clone(shipped.node());
  node["model"]["turbine_file"] = std::filesystem::absolute(turbine_file).string();
  node["name"] = shipped.get<std::string>("name", "design") + " for " +
                 std::filesystem::path(turbine_file).filename().string();
  if (model.get<std::string>("subsystem", "drive_train") == "drive_train") {
    // Rated torques P / omega: aerodynamic (rotor side) and generator; the aerodynamic torque's slope with
    // rotor speed scales as that torque over the rated rotor speed.
    const double aero =
        (to.rated_power / to.rated_rotor_speed()) / (from.rated_power / from.rated_rotor_speed());
    const double generator =
        (to.rated_power / to.rated_generator_speed) / (from.rated_power / from.rated_generator_speed);
    const double damping = aero * from.rated_rotor_speed() / to.rated_rotor_speed();
    if (model.has("aero_damping"))
      node["model"]["aero_damping"] = model.get_number("aero_damping", 0.0, 0.0, 1e12) * damping;
    if (model.has("input_bound")) {
      const Eigen::MatrixXd bound = yaml_matrix(model, "input_bound");
      if (bound.size() != 2) throw model.error("input_bound", "a drive train has two inputs");
      node["model"]["input_bound"] = std::vector<double>{bound(0) * aero, bound(1) * generator};
    }
  }
  return load_design_input(YamlSection(node, template_file));
}

GainFile gain_for_turbine(const GainFile& gain, const std::string& gain_key, const std::string& design_file,
                          const std::string& turbine_file, const TurbineParams& turbine, bool design,
                          std::string& note) {
  if (gain_fits_turbine(gain, turbine)) return gain;
  const std::string what = gain.file + " was designed for another turbine than " + turbine_file;
  if (!design)
    throw ConfigError(gain.file, 0, gain_key,
                      what + ": design one (windfdi-qb-design on a copy of " + design_file +
                          " with its turbine_file) or set design_for_turbine: true");
  const DesignInput in = design_for_turbine(design_file, turbine_file);
  const QbSolution sol = in.fixed_alpha ? qb_solve(in.problem, in.alpha) : qb_design(in.problem, in.search);
  if (!sol.feasible)
    throw ConfigError(design_file, 0, gain_key,
                      what + ", and its design for it is infeasible: " + sol.message);
  GainFile g = parse_gain_file(gain_file_text(in, sol, design_file), design_file + " for " + turbine_file);
  char buf[160];
  std::snprintf(buf, sizeof buf, ": designed from %s for it (alpha %.3g, closed-loop radius %.6f, %.2f s)",
                std::filesystem::path(design_file).filename().c_str(), sol.alpha, sol.closed_loop_radius,
                sol.seconds);
  note = what + buf;
  return g;
}

}  // namespace windfdi::sensor_bias
