// One turbine's speed and pitch sensor-bias estimation and detection (Witczak et al.): drive-train and pitch
// observers.
#include "bias_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace windfdi::sensor_bias {

const std::array<const char*, kChannels>& channel_components() {
  static const std::array<const char*, kChannels> c = {"rotor_speed_sensor", "generator_speed_sensor",
                                                       "pitch_sensor_1", "pitch_sensor_2", "pitch_sensor_3"};
  return c;
}

BiasConfig load_bias_config(const YamlSection& s, const std::string& default_gain_dir,
                            const TurbineParams& turbine) {
  s.require_known_keys({"turbine_file",
                        "mode",
                        "drive_train_gains",
                        "pitch_gains",
                        "paper_drive_train_gains",
                        "paper_pitch_gains",
                        "threshold_speed_share",
                        "threshold_rotor_speed",
                        "threshold_generator_speed",
                        "threshold_pitch",
                        "raise_time",
                        "clear_ratio",
                        "clear_time",
                        "filter_time",
                        "settle_time",
                        "max_bridged_gap",
                        "reconfiguration_hold",
                        "witness_torque_share",
                        "witness_torque_min",
                        "witness_gate_on_model",
                        "converter_offset_time",
                        "max_tracking_error",
                        "stuck_time",
                        "stuck_samples",
                        "stuck_after_raise",
                        "type_evidence",
                        "type_evidence_at_deadline",
                        "type_evidence_small_sample",
                        "type_decision_time_rotor_speed",
                        "type_decision_time_generator_speed",
                        "type_decision_time_generator_speed_below_rated",
                        "type_decision_time_pitch",
                        "type_misfit_max",
                        "type_lag_ratio_max",
                        "differential_confirm",
                        "pitch_offset_confirm",
                        "pitch_offset_time",
                        "rotor_speed_max",
                        "generator_speed_max",
                        "torque_max",
                        "wind_max",
                        "pitch_min",
                        "pitch_max",
                        "design_for_turbine",
                        "drive_train_design",
                        "pitch_design"});
  BiasConfig c;
  c.mode =
      s.get_choice("mode", "observer", {"observer", "paper"}) == "paper" ? Mode::kPaper : Mode::kObserver;
  auto path = [&](const char* key, const std::string& fallback) {
    return s.get_path(key, (std::filesystem::path(default_gain_dir) / fallback).string());
  };
  if (c.mode == Mode::kObserver) {
    c.drive_train_gain_file = path("drive_train_gains", "gains_drive_train_observer.yaml");
    c.pitch_gain_file = path("pitch_gains", "gains_pitch_observer.yaml");
    c.design_for_turbine = s.get<bool>("design_for_turbine", c.design_for_turbine);
    c.drive_train_design = path("drive_train_design", "design_drive_train_observer.yaml");
    c.pitch_design = path("pitch_design", "design_pitch_observer.yaml");
  } else {
    c.drive_train_gain_file = path("paper_drive_train_gains", "gains_drive_train_paper.yaml");
    c.pitch_gain_file = path("paper_pitch_gains", "gains_pitch_paper.yaml");
  }
  // The turbine's own scale: a share of its rated speeds and torque, unless given in absolute units.
  const double speed_share = s.get_number("threshold_speed_share", 0.01, 1e-4, 0.5);
  c.threshold[0] =
      s.get_number("threshold_rotor_speed", speed_share * turbine.rated_rotor_speed(), 1e-6, 5.0);
  c.threshold[1] =
      s.get_number("threshold_generator_speed", speed_share * turbine.rated_generator_speed, 1e-4, 400.0);
  c.threshold[2] = c.threshold[3] = c.threshold[4] =
      s.get_number("threshold_pitch", c.threshold[2], 1e-4, 90.0);
  c.raise_time = s.get_number("raise_time", c.raise_time, 0.0, 3600.0);
  c.clear_ratio = s.get_number("clear_ratio", c.clear_ratio, 0.0, 1.0);
  c.clear_time = s.get_number("clear_time", c.clear_time, 0.0, 3600.0);
  c.filter_time = s.get_number("filter_time", c.filter_time, 0.0, 600.0);
  c.settle_time = s.get_number("settle_time", c.settle_time, 0.0, 3600.0);
  c.max_bridged_gap = s.get_number("max_bridged_gap", c.max_bridged_gap, 0.0, 10.0);
  c.reconfiguration_hold = s.get_number("reconfiguration_hold", c.reconfiguration_hold, 0.0, 600.0);
  c.witness_torque_min = s.get_number(
      "witness_torque_min",
      s.get_number("witness_torque_share", 0.1, 0.0, 1.0) * turbine.rated_generator_torque(), 1.0, 1e9);
  c.witness_gate_on_model = s.get<bool>("witness_gate_on_model", c.witness_gate_on_model);
  c.converter_offset_time = s.get_number("converter_offset_time", c.converter_offset_time, 0.0, 3600.0);
  c.max_tracking_error = s.get_number("max_tracking_error", c.max_tracking_error, 0.0, 90.0);
  c.stuck_time = s.get_number("stuck_time", c.stuck_time, 0.0, 60.0);
  c.stuck_samples = static_cast<int>(s.get_number("stuck_samples", c.stuck_samples, 0.0, 100000.0));
  c.stuck_after_raise = s.get<bool>("stuck_after_raise", c.stuck_after_raise);
  c.type_evidence = s.get_number("type_evidence", c.type_evidence, 0.0, 1e6);
  c.type_evidence_at_deadline =
      s.get_number("type_evidence_at_deadline", c.type_evidence_at_deadline, 0.0, c.type_evidence);
  c.type_evidence_small_sample = s.get<bool>("type_evidence_small_sample", c.type_evidence_small_sample);
  c.type_decision_time[0] =
      s.get_number("type_decision_time_rotor_speed", c.type_decision_time[0], 0.0, 3600.0);
  c.type_decision_time[1] =
      s.get_number("type_decision_time_generator_speed", c.type_decision_time[1], 0.0, 3600.0);
  c.type_decision_time_generator_below_rated =
      s.get_number("type_decision_time_generator_speed_below_rated",
                   c.type_decision_time_generator_below_rated, 0.0, 3600.0);
  c.type_decision_time[2] = c.type_decision_time[3] = c.type_decision_time[4] =
      s.get_number("type_decision_time_pitch", c.type_decision_time[2], 0.0, 3600.0);
  c.type_misfit_max = s.get_number("type_misfit_max", c.type_misfit_max, 0.0, 1e9);
  c.type_lag_ratio_max = s.get_number("type_lag_ratio_max", c.type_lag_ratio_max, 0.0, 100.0);
  c.differential_confirm = s.get_number("differential_confirm", c.differential_confirm, 0.0, 1.0);
  c.pitch_offset_confirm = s.get_number("pitch_offset_confirm", c.pitch_offset_confirm, 0.0, 10.0);
  c.pitch_offset_time = s.get_number("pitch_offset_time", c.pitch_offset_time, 0.1, 600.0);
  // Plausible ranges are multiples of the turbine's rated values (the benchmark's 5 rad/s, 400 rad/s and 1e6
  // N m there), so that a faster rotor or a larger generator is not rejected sample by sample.
  c.rotor_speed_max = s.get_number("rotor_speed_max", 2.93 * turbine.rated_rotor_speed(), 0.1, 100.0);
  c.generator_speed_max =
      s.get_number("generator_speed_max", 2.47 * turbine.rated_generator_speed, 1.0, 10000.0);
  c.torque_max = s.get_number("torque_max", 33.0 * turbine.rated_generator_torque(), 1.0, 1e9);
  c.wind_max = s.get_number("wind_max", c.wind_max, 1.0, 200.0);
  c.pitch_min = s.get_number("pitch_min", c.pitch_min, -90.0, 90.0);
  c.pitch_max = s.get_number("pitch_max", c.pitch_max, c.pitch_min, 180.0);
  return c;
}

namespace {

template <class Obs>
void load_into(Obs& o, const GainFile& g, const char* what) {
  if (g.A.rows() != o.A.rows() || g.B.cols() != o.B.cols() || g.C.rows() != o.C.rows())
    throw ConfigError(g.file, 0, "A",
                      std::string(what) + ": expected " + std::to_string(o.A.rows()) + " states, " +
                          std::to_string(o.B.cols()) + " inputs, " + std::to_string(o.C.rows()) +
                          " outputs; the gain file has " + std::to_string(g.A.rows()) + ", " +
                          std::to_string(g.B.cols()) + ", " + std::to_string(g.C.rows()));
  o.A = g.A;
  o.B = g.B;
  o.C = g.C;
  o.K = g.K;
}

bool in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

BiasEstimator::BiasEstimator(const BiasConfig& config, const GainFile& dt, const GainFile& pitch,
                             const TurbineParams& turbine)
    : cfg_(config), turbine_(turbine), aero_(turbine), aero_damping_(dt.aero_damping) {
  const bool paper = cfg_.mode == Mode::kPaper;
  if ((dt.structure == "paper") != paper || (pitch.structure == "paper") != paper)
    throw ConfigError(
        paper ? dt.file : pitch.file, 0, "structure",
        std::string("mode ") + (paper ? "paper" : "observer") + " needs gain files of that structure");
  if (paper) {
    load_into(dt_paper_, dt, "drive train (paper mode)");
    for (auto& p : pitch_paper_) load_into(p, pitch, "pitch (paper mode)");
  } else {
    load_observer(dt_obs_, dt, 5, "drive train (observer mode)");
    for (auto& p : pitch_obs_) load_observer(p, pitch, 3, "pitch (observer mode)");
  }
  // The converter is first order: over a sample of T the mean torque moves (tau/T)(1 - exp(-T/tau)) of the
  // way from the measured torque to its reference.
  const double T = dt.sample_time, tau = turbine.converter_time_constant;
  dt_ = T;
  pitch_offset_forget_ = std::exp(-T / cfg_.pitch_offset_time);
  rate_a_ =
      1.0 - std::exp(-T / 0.1);  // the reference rate low-passed over 0.1 s (the actuator's own time scale)
  torque_avg_ = tau > 0.0 ? 1.0 - tau / T * (1.0 - std::exp(-T / tau)) : 1.0;
  converter_a_ = tau > 0.0 ? 1.0 - std::exp(-T / tau) : 1.0;
  converter_offset_a_ =
      cfg_.converter_offset_time > 0.0 ? 1.0 - std::exp(-T / cfg_.converter_offset_time) : 0.0;
  auto inv = [](double b) { return b > 0.0 ? 1.0 / b : 0.0; };
  for (int j = 0; j < 2; ++j)
    inv_bias_bound_[static_cast<std::size_t>(j)] = dt.bias_bound.size() > j ? inv(dt.bias_bound(j)) : 0.0;
  for (int j = 2; j < kChannels; ++j)
    inv_bias_bound_[static_cast<std::size_t>(j)] =
        pitch.bias_bound.size() > 0 ? inv(pitch.bias_bound(0)) : 0.0;
  filter_a_ = cfg_.filter_time > 0.0 ? 1.0 - std::exp(-dt.sample_time / cfg_.filter_time) : 1.0;
  // The rotor speed's test averages 0.5 s blocks: its witness (the generator speed over the gear ratio)
  // carries the drive train's torsional oscillation, which the rotor does not, and which sample by sample
  // correlates with the witness itself. The generator speed is regressed on its own reading (the witness's
  // noise would otherwise be shared by the error and the regressor), in 0.1 s blocks (its residual, the
  // converter model's error and the controller's response, is correlated over a few samples, which sample by
  // sample would count as independent evidence: in closed loop that decided 3 of 55 faults wrongly at 16),
  // and the pitch on its reference, sample by sample.
  const bool small_sample = cfg_.type_evidence_small_sample;
  fault_type_[0] = GainOrOffsetTest(std::max(1, static_cast<int>(std::lround(0.5 / T))), false, small_sample);
  fault_type_[1] = GainOrOffsetTest(std::max(1, static_cast<int>(std::lround(0.1 / T))), true, small_sample);
  for (std::size_t j = 2; j < static_cast<std::size_t>(kChannels); ++j)
    fault_type_[j] = GainOrOffsetTest(1, false, small_sample);
}

double BiasEstimator::aero_torque(const FrameSample& s) const {
  if (std::isfinite(s.aero_torque)) return s.aero_torque;
  if (!in(s.wind_hub, 0.0, cfg_.wind_max)) return kNaN;
  // The model on measured wind and the bias-free rotor speed and pitch (a biased sensor must not bias the
  // input).
  const double omega = cfg_.mode == Mode::kPaper ? dt_paper_.state()(0) : dt_obs_.state()(0);
  const double w = std::clamp(omega, 0.05, cfg_.rotor_speed_max);
  // One evaluation at the rotor-average pitch (the plant averages three blade evaluations; the IPC's 1P
  // offsets cancel in the mean pitch and their second-order effect is far below the measured-wind error).
  double beta = 0.0;
  for (int i = 0; i < kBlades; ++i) {
    const std::size_t c = static_cast<std::size_t>(2 + i);
    const double b = (context_.absent & (kValidPitch1 << i))    ? turbine_.fixed_pitch
                     : pitch_init_[static_cast<std::size_t>(i)] ? out_.corrected[c]
                                                                : s.pitch[static_cast<std::size_t>(i)];
    if (!std::isfinite(b)) return kNaN;
    beta += b / kBlades;
  }
  return aero_.aero_torque(s.wind_hub, w, std::clamp(beta, turbine_.pitch_min - 5.0, turbine_.pitch_max));
}

bool BiasEstimator::update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) {
  fresh_ = true;
  if (!std::isfinite(s.t)) {
    ++rejected_;
    return false;
  }
  bool all_ok = true;
  // Re-settle after a long hole: the observers missed too much. A short one (a loaded host losing 20 samples
  // every few seconds) moves the observers by a few samples' worth, well inside their noise; re-settling on
  // each left nothing ever raised.
  const bool long_gap = gap && !(start_ >= 0.0 && bridgeable_hole(last_sequence_, last_t_, s.sequence, s.t,
                                                                  cfg_.max_bridged_gap));
  // s since the last sample fed: a hole's reference moved over all of it, not over one sample period.
  const double since_last = gap && start_ >= 0.0 && s.t > last_t_ ? s.t - last_t_ : dt_;
  last_t_ = s.t;
  last_sequence_ = s.sequence;
  if (long_gap) start_ = -1.0;
  if (start_ < 0.0) start_ = s.t;
  // A reading repeated to the last bit is a stuck sensor (a healthy one carries noise).
  const double readings[kChannels] = {s.rotor_speed, s.generator_speed, s.pitch[0], s.pitch[1], s.pitch[2]};
  for (std::size_t k = 0; k < static_cast<std::size_t>(kChannels); ++k) {
    reading_repeats_[k] = readings[k] == last_reading_[k] && !gap ? reading_repeats_[k] + 1 : 0;
    last_reading_[k] = readings[k];
  }
  out_.t = s.t;
  const bool paper = cfg_.mode == Mode::kPaper;

  // Pitch, blade by blade: state [beta, beta_dot, bias] driven by the reference.
  for (int i = 0; i < kBlades; ++i) {
    const std::size_t c = static_cast<std::size_t>(2 + i);
    const double y = s.pitch[static_cast<std::size_t>(i)], r = s.pitch_ref[static_cast<std::size_t>(i)];
    const bool ok = in(y, cfg_.pitch_min, cfg_.pitch_max) && in(r, cfg_.pitch_min, cfg_.pitch_max) &&
                    (s.valid_mask & (kValidPitch1 << i)) && (s.valid_mask & (kValidPitchRef1 << i));
    if (!ok) {
      // A pitch the data does not carry at all is a blade not diagnosed (said at start), not a rejected
      // sample.
      const uint32_t bits = (kValidPitch1 | kValidPitchRef1) << i;
      if ((context_.absent & bits) == 0) all_ok = false;
      continue;
    }
    const Eigen::Matrix<double, 1, 1> yv(y), uv(r);
    const std::size_t b = static_cast<std::size_t>(i);
    auto& fit = pitch_offset_[b];
    // deg since the last valid sample (the offset fit keeps that reference)
    const double reference_step = fit.started ? std::fabs(r - fit.last_ref) : 0.0;
    if (!paper) {
      // The actuator is outrun by a reference that moves faster than its rate limit (the arbiter's, or the
      // turbine's): a safe stop's jump to feather, a reconfiguration's step, a derated blade. The
      // controller's own reference moves at up to 9.8 deg/s under the 10 deg/s limit (21 m/s, TI 0.16), so a
      // fifth above the limit is a jump. The actuator then runs at its rate limit until the pitch, corrected
      // by the bias known before the jump, is back near its reference: a healthy blade tracks within 1.5 deg.
      const double rate_limit = std::min(turbine_.pitch_rate_limit, context_.pitch_rate_limit[b]);
      if (reference_step > kOutrunRatio * rate_limit * since_last) outrun_[b] = true;
      const double held_bias = pitch_init_[b] ? pitch_obs_[b].state()(2) : 0.0;
      if (std::fabs(r - (y - held_bias)) <= 0.5 * cfg_.max_tracking_error) outrun_[b] = false;
    }
    if (!paper && (gap || (cfg_.max_tracking_error > 0.0 && outrun_[b] && y != last_pitch_[b]))) {
      // The offset fit and the gain-or-offset record model a linear lag; a rate-limited actuator's error is
      // no lag: a derate to 5 deg/s that the controller outran near rated wind took a biased blade's offset
      // to 0 and cleared its bias (the reliability campaign). They follow the reference only. A reading
      // repeated to the bit (a stuck sensor) is no outrun actuator. Nor is the first sample after a hole
      // one lag's worth of error: the reference moved through the hole.
      fit.follow(r, dt_, rate_a_);
    } else {
      fit.update(y - r, r, dt_, pitch_offset_forget_, rate_a_);
      fault_type_[c].add(y - r, r, fit.v_lp);
    }
    if (paper) {
      auto& e = pitch_paper_[static_cast<std::size_t>(i)];
      if (!pitch_init_[static_cast<std::size_t>(i)]) e.reset(Eigen::Vector2d(y, 0.0));
      out_.bias[c] = e.step(yv, uv)(0);
    } else {
      auto& o = pitch_obs_[static_cast<std::size_t>(i)];
      if (!pitch_init_[static_cast<std::size_t>(i)]) o.reset(Eigen::Vector4d(y, 0.0, 0.0, 0.0));
      const Eigen::Vector2d held = o.state().tail<2>();
      o.step(yv, uv);
      repeated_[b] = y == last_pitch_[b] ? repeated_[b] + 1 : 0;
      last_pitch_[b] = y;
      const bool stuck = cfg_.stuck_time > 0.0 && repeated_[b] * dt_ >= cfg_.stuck_time;
      // Three things hold the bias (and its rate) while the angle follows the measurement:
      // - the first sample after lost ones: the blade moved through the hole, and one observer step takes all
      //   of that motion as innovation. A soak's host starved for 2-3 s took healthy blades' biases to
      //   +-2.8-4.1 deg, where the outrun hold then kept them for good (its release compares the pitch
      //   corrected by that bias with the reference), and cleared a real 1 deg bias;
      // - another service (pitch_diag) reporting this blade's actuator: the observer's healthy actuator model
      //   would turn the actuator's fault into a sensor bias;
      // - an outrun (rate-limited) actuator: the measured 28-31 deg lag of a safe stop's feathering ramp read
      //   as a bias on healthy blades (end to end).
      const bool actuator_hold = !gap && context_.pitch_actuator_suspect[b];
      const bool tracking_hold =
          !gap && !actuator_hold && !stuck && cfg_.max_tracking_error > 0.0 && outrun_[b];
      if (gap || actuator_hold || tracking_hold) {
        o.state().tail<2>() = held;
        o.state()(0) = y - held(0);
      }
      if (actuator_hold) ++actuator_holds_;
      if (tracking_hold) ++tracking_holds_;
      // The actuator is rate limited: so is its model's prediction (a saturated reference step is not a
      // bias).
      o.state()(1) = std::clamp(o.state()(1), -turbine_.pitch_rate_limit, turbine_.pitch_rate_limit);
      out_.bias[c] = o.state()(2);
    }
    pitch_init_[static_cast<std::size_t>(i)] = true;
    out_.corrected[c] = y - out_.bias[c];
  }

  // Drive train: state [omega_r, omega_g, theta, b_r, b_g], inputs [T_aero, T_g].
  const bool speeds_ok =
      in(s.rotor_speed, 0.0, cfg_.rotor_speed_max) && in(s.generator_speed, 0.0, cfg_.generator_speed_max) &&
      in(s.gen_torque, -cfg_.torque_max, cfg_.torque_max) && (s.valid_mask & kValidRotorSpeed) &&
      (s.valid_mask & kValidGeneratorSpeed) && (s.valid_mask & kValidGenTorque);
  double ta = kNaN;
  if (speeds_ok) {
    if (!dt_init_) {
      // Start at the measured speeds and the torsion that carries the measured generator torque.
      const double theta = turbine_.gear_ratio *
                           (s.gen_torque + turbine_.generator_friction * s.generator_speed) /
                           (turbine_.drive_train_efficiency * turbine_.drive_train_stiffness);
      if (paper)
        dt_paper_.reset(Eigen::Vector3d(s.rotor_speed, s.generator_speed, theta));
      else
        dt_obs_.reset(
            (Eigen::Matrix<double, 7, 1>() << s.rotor_speed, s.generator_speed, theta, 0.0, 0.0, 0.0, 0.0)
                .finished());
    }
    ta = aero_torque(s);
  }
  if (speeds_ok && in(ta, -cfg_.torque_max * 100.0, cfg_.torque_max * 100.0)) {
    const double tg = std::isfinite(s.gen_torque_ref) && std::fabs(s.gen_torque_ref) <= cfg_.torque_max
                          ? s.gen_torque + torque_avg_ * (s.gen_torque_ref - s.gen_torque)
                          : s.gen_torque;
    // The design's A holds -k_a omega_r (linearised aerodynamic damping); the input adds it back, so the
    // model integrates the full nonlinear T_aero(omega_r) while the gain was designed for the damped error
    // dynamics.
    const double omega_hat = paper ? dt_paper_.state()(0) : dt_obs_.state()(0);
    const Eigen::Vector2d y(s.rotor_speed, s.generator_speed), u(ta + aero_damping_ * omega_hat, tg);
    // The gain-or-offset test takes the torque from the converter's first-order response to its reference,
    // which carries no measurement noise: the witness's noise falls from 0.5 to 0.06-0.1 rad/s, and a
    // generator-speed fault's type is decided in 1-5 s instead of 5-20 s.
    converter_torque_ = converter_init_ && !gap
                            ? converter_torque_ + converter_a_ * (last_torque_ref_ - converter_torque_)
                            : s.gen_torque;
    // The converter's own offset, learned slowly: the model stays free of the torque sensor's noise and
    // the witness free of the offset (converter_offset_time). Kept over holes: it is the converter's, not
    // the model's. Held while a speed channel's gain-or-offset record runs: the learned offset wanders
    // (+-5 N m over 10 s on the 1.5 MW rotor), and a witness that wanders within a record reads as evidence.
    if (converter_init_ && !gap && quiet(0) && quiet(1))
      converter_offset_ += converter_offset_a_ * (s.gen_torque - converter_torque_ - converter_offset_);
    converter_init_ = true;
    last_torque_ref_ = std::isfinite(s.gen_torque_ref) && std::fabs(s.gen_torque_ref) <= cfg_.torque_max
                           ? s.gen_torque_ref
                           : s.gen_torque;
    const double delivered_torque = converter_torque_ + converter_offset_;
    out_.witness_speed = kNaN;
    // The generator speed from the electrical power, P = eta_g T_g omega_g, with the measured torque of the
    // same sample (independent sensors; no speed sensor enters it); unusable when missing or at low torque.
    // Whether the torque is high enough is asked of the converter model, not of the measured sample: gated on
    // the sample itself, near the gate the witness kept only the samples whose torque noise was positive and
    // read them low (the example 1.5 MW rotor at 4.7 m/s, turbulence 0.19, torque 700-900 N m against its 798
    // N m gate: the witness 12 % low, and a healthy generator speed reported at +12 rad/s).
    const double gate_torque = cfg_.witness_gate_on_model ? delivered_torque : s.gen_torque;
    const double power_speed = gate_torque >= cfg_.witness_torque_min && s.gen_torque > 0.0
                                   ? s.power / (turbine_.generator_efficiency * s.gen_torque)
                                   : kNaN;
    const bool witness_ok = (s.valid_mask & kValidPower) && std::isfinite(s.power) && s.power > 0.0 &&
                            power_speed <= cfg_.generator_speed_max;
    const double wg = witness_ok ? power_speed : kNaN;
    if (witness_ok) filtered_power_ += filter_a_ * (s.power - filtered_power_);
    if (witness_ok && delivered_torque >= cfg_.witness_torque_min) {
      const double w = s.power / (turbine_.generator_efficiency * delivered_torque);
      fault_type_[0].add(s.rotor_speed - w / turbine_.gear_ratio, w / turbine_.gear_ratio);
      fault_type_[1].add(s.generator_speed - w, s.generator_speed);
    }
    if (paper) {
      const auto& f = dt_paper_.step(y, u);
      out_.bias[0] = f(0);
      out_.bias[1] = f(1);
      for (int j = 0; j < 3; ++j) out_.drive_train_state[static_cast<std::size_t>(j)] = dt_paper_.state()(j);
    } else {
      // Third output: the power witness; without it the observer predicts it (zero innovation).
      const Eigen::Vector3d y3(s.rotor_speed, s.generator_speed, wg);
      // Not producing (a stop ramps the torque to zero, idling): the witness is gone and the common mode
      // unobservable (README); a safe stop drifted the rotor-speed bias past its threshold. Hold the biases.
      // Held too from the arbiter's safe stop on: feathering at the rate limit takes the aerodynamic torque
      // model far from where it holds while the torque is still up (the example 2 MW turbine: a +3 to +5.6
      // rad/s generator-speed "bias" 20 s into each of six stops of its multi-fault suite).
      const bool producing = gate_torque >= cfg_.witness_torque_min && !context_.turbine_stopped;
      const Eigen::Matrix<double, 4, 1> held = dt_obs_.state().tail<4>();
      if (witness_ok) {
        dt_obs_.step(y3, u);
        out_.witness_speed = wg;
        ++witness_used_;
      } else {
        dt_obs_.step_without(Eigen::Vector3d(y3(0), y3(1), 0.0), u, 2);
      }
      if (!producing || gap) dt_obs_.state().tail<4>() = held;
      if (gap) {
        // After lost samples, as the pitch above: the speeds moved through the hole; the biases are held and
        // the speed states start from the measurements they correct.
        dt_obs_.state()(0) = s.rotor_speed - held(0);
        dt_obs_.state()(1) = s.generator_speed - held(1);
      }
      out_.bias[0] = dt_obs_.state()(3);
      out_.bias[1] = dt_obs_.state()(4);
      for (int j = 0; j < 3; ++j) out_.drive_train_state[static_cast<std::size_t>(j)] = dt_obs_.state()(j);
    }
    out_.corrected[0] = s.rotor_speed - out_.bias[0];
    out_.corrected[1] = s.generator_speed - out_.bias[1];
    out_.aero_torque = ta;
    out_.differential = out_.bias[0] - out_.bias[1] / turbine_.gear_ratio;
    dt_init_ = true;
    ++fed_dt_;
  } else {
    all_ok = false;
    converter_init_ = false;  // the converter model restarts from the next measured torque
  }
  if (!all_ok) ++rejected_;
  double ratio = 0.0;
  for (std::size_t c = 0; c < kChannels; ++c)
    ratio = std::max(ratio, std::fabs(out_.bias[c]) * inv_bias_bound_[c]);
  out_.bound_ratio = ratio;
  has_output_ = dt_init_ || pitch_init_[0] || pitch_init_[1] || pitch_init_[2];
  detect(s.t, events);
  return all_ok;
}

void BiasEstimator::OffsetFit::update(double r, double ref, double dt, double forget, double rate_a) {
  if (!started) {
    started = true;
    last_ref = ref;
  }
  v_lp += rate_a * ((ref - last_ref) / dt - v_lp);
  last_ref = ref;
  s11 = forget * s11 + 1.0;
  s1v = forget * s1v + v_lp;
  svv = forget * svv + v_lp * v_lp;
  s1r = forget * s1r + r;
  svr = forget * svr + v_lp * r;
}

void BiasEstimator::OffsetFit::follow(double ref, double dt, double rate_a) {
  if (!started) {
    started = true;
    last_ref = ref;
  }
  v_lp += rate_a * ((ref - last_ref) / dt - v_lp);
  last_ref = ref;
}

double BiasEstimator::OffsetFit::offset() const {
  // Normal equations of [1 -v] [b tau]^T = r; a window without reference motion leaves tau undetermined, and
  // then the offset is the plain mean.
  const double det = s11 * svv - s1v * s1v;
  if (s11 <= 0.0) return 0.0;
  if (det <= 1e-9 * s11 * (svv + 1e-12)) return s1r / s11;
  return (svv * s1r - s1v * svr) / det;
}

const char* BiasEstimator::fault_class(std::size_t k, double waited) {
  if (reading_stuck(k)) return "sensor_stuck";
  if (cfg_.type_evidence <= 0.0) return "sensor_bias";
  // A pitch error that is neither an offset nor a gain of the reading (the full model fits far better than
  // either) is the blade's dynamics: a slow actuator answers the IPC's 1P swing with less amplitude while its
  // mean stays right, which alone read as a sensor gain of 0.68-0.95 (evidence up to 1500) on abrupt leaks.
  // pitch_diag owns it; nothing is raised here while it lasts.
  if (k >= 2 && cfg_.type_misfit_max > 0.0 && fault_type_[k].misfit() >= cfg_.type_misfit_max) return nullptr;
  GainOrOffsetTest::Verdict verdict = fault_type_[k].verdict(cfg_.type_evidence);
  if (verdict == GainOrOffsetTest::Verdict::kUndecided) {
    const bool below_rated = filtered_power_ < kBelowRatedPowerShare * turbine_.rated_power;
    const double deadline =
        k == 1 && below_rated ? cfg_.type_decision_time_generator_below_rated : cfg_.type_decision_time[k];
    if (waited < deadline - 1e-9) return nullptr;
    verdict = fault_type_[k].verdict_now(cfg_.type_evidence_at_deadline);
  }
  const bool gain = verdict == GainOrOffsetTest::Verdict::kGain;
  // A slower actuator (a leak) in region 3 makes an error the offset or gain model still fits (misfit 0.1,
  // a gain of 0.93 with evidence 139; fault suite set 168, scenario 05): only its lag tells it from a sensor.
  // The lag counts only where it is known: three standard errors above the limit. A reference that hardly
  // moved fits lags of -16 to +18 s to real pitch-sensor offsets (standard errors up to 10^4 s), and a
  // second of record after an offset's onset 1.0 +- 0.39 s: the 100 Hz residuals are not white, so the
  // standard error is optimistic and two of them were not enough.
  if (k >= 2 && cfg_.type_lag_ratio_max > 0.0) {
    const GainOrOffsetTest::Nuisance lag = fault_type_[k].nuisance(gain);
    if (-lag.coefficient - 3.0 * lag.standard_error > cfg_.type_lag_ratio_max * healthy_pitch_lag())
      return nullptr;
  }
  return gain ? "sensor_gain" : "sensor_bias";
}

std::string BiasEstimator::detail(std::size_t k, bool raised) const {
  static const char* kUnit[] = {"rad/s", "rad/s", "deg", "deg", "deg"};
  const std::string fault = raised_class_[k];
  const GainOrOffsetTest& type = fault_type_[k];
  const char* cleared = raised ? "" : "cleared: ";
  const bool decided = raised_verdict_[k] != GainOrOffsetTest::Verdict::kUndecided;
  const char* mode = cfg_.mode == Mode::kPaper ? "paper" : "observer";
  const char* how = decided ? "" : "; the likelier: the quantity varied little";
  char d[320];
  if (fault == "sensor_stuck")
    std::snprintf(d, sizeof d,
                  "%sreading stuck at %.6g %s, %+.4g %s from the estimated value (threshold %.4g)", cleared,
                  last_reading_[k], kUnit[k], filtered_[k], kUnit[k], cfg_.threshold[k]);
  else if (fault == "sensor_gain")
    std::snprintf(
        d, sizeof d,
        "%sgain %.4g (evidence %.1f against an offset%s); estimated bias now %+.4g %s (threshold %.4g)",
        cleared, type.gain(), type.evidence(), how, filtered_[k], kUnit[k], cfg_.threshold[k]);
  else if (cfg_.type_evidence <= 0.0)
    std::snprintf(d, sizeof d, "%sestimated bias %+.4g %s (threshold %.4g, %s mode)", cleared, filtered_[k],
                  kUnit[k], cfg_.threshold[k], mode);
  else if (!(std::fabs(type.gain() - 1.0) <= 1.0))
    std::snprintf(d, sizeof d, "%sestimated bias %+.4g %s (an offset: no gain fits; threshold %.4g, %s mode)",
                  cleared, filtered_[k], kUnit[k], cfg_.threshold[k], mode);
  else
    std::snprintf(d, sizeof d,
                  "%sestimated bias %+.4g %s (an offset: evidence %.1f against a gain of %.4g%s; threshold "
                  "%.4g, %s mode)",
                  cleared, filtered_[k], kUnit[k], -type.evidence(), type.gain(), how, cfg_.threshold[k],
                  mode);
  std::string out = d;
  if (k >= 2 && fault != "sensor_stuck" && cfg_.type_evidence > 0.0 && type.blocks() > 3) {
    // The actuator's lag behind the reference that the reported model fits (what type_lag_ratio_max judges).
    const GainOrOffsetTest::Nuisance lag = type.nuisance(fault == "sensor_gain");
    std::snprintf(d, sizeof d, "; fitted actuator lag %.3g s (+-%.2g)", -lag.coefficient, lag.standard_error);
    out += d;
  }
  return out;
}

void BiasEstimator::detect(double t, std::vector<FaultEvent>& events) {
  const double a = filter_a_;
  filtered_diff_ += a * (out_.differential - filtered_diff_);
  for (int c = 0; c < kChannels; ++c) {
    const std::size_t k = static_cast<std::size_t>(c);
    filtered_[k] += a * (out_.bias[k] - filtered_[k]);
    // The gain-or-offset record starts at the onset: while the channel is quiet it is restarted.
    if (quiet(k)) fault_type_[k].restart();
    if (t - start_ < cfg_.settle_time) {
      above_since_[k] = below_since_[k] = -1.0;
      continue;
    }
    if (k >= 2 && t - reconfigured_at_ < cfg_.reconfiguration_hold) {
      // The blades' rate limits or the stop just changed: the pitch's transient is no new fault, and no
      // reason to clear one either.
      above_since_[k] = below_since_[k] = -1.0;
      continue;
    }
    const double thr = cfg_.threshold[k];
    double stat = std::fabs(filtered_[k]);
    if (c < 2 && cfg_.mode == Mode::kObserver) {
      // Which speed sensor: its own estimate (placed by the power witness) must be confirmed by the
      // differential the two speed sensors see without any model, with the sign a bias on that sensor gives
      // it (rotor: +b_r, generator: -b_g / N). A common-mode offset (power or torque channel wrong, or both
      // sensors alike) has no differential and flags neither sensor. Statistic: min(|b|, d_along / confirm),
      // so it reaches the threshold only when both do their share.
      const double d = c == 0 ? filtered_diff_ : -filtered_diff_ * turbine_.gear_ratio;
      const double along = filtered_[k] >= 0.0 ? d : -d;
      if (cfg_.differential_confirm > 0.0)
        stat = std::min(stat, std::max(0.0, along) / cfg_.differential_confirm);
    } else if (c >= 2 && cfg_.mode == Mode::kObserver && cfg_.pitch_offset_confirm > 0.0) {
      // Which fault of the blade: its static offset (lag removed) must carry the bias (same sign), as min()
      // above.
      const double m = pitch_offset_[k - 2].offset();
      const double along = filtered_[k] >= 0.0 ? m : -m;
      stat = std::min(stat, std::max(0.0, along) / cfg_.pitch_offset_confirm);
    }
    auto event = [&](bool raised, double since) {
      FaultEvent e;
      e.t = t;
      e.t_detected = since;
      e.source = "sensor_bias";
      e.component = channel_components()[k];
      e.fault = raised_class_[k];
      e.raised = raised;
      e.severity = "fault";
      e.statistic = stat;
      e.threshold = thr;
      e.size = filtered_[k];
      e.detail = detail(k, raised);
      events.push_back(e);
    };
    // What the raise keeps of the channel: the class, its type verdict and gain, and the reading (a stuck
    // report stands while the reading stays at it).
    auto mark_raised = [&](const char* fault) {
      raised_[k] = true;
      raised_class_[k] = fault;
      raised_verdict_[k] = fault_type_[k].verdict(cfg_.type_evidence);
      raised_gain_[k] = fault_type_[k].gain();
      raised_reading_[k] = last_reading_[k];
      below_since_[k] = -1.0;
    };
    if (!raised_[k]) {
      if (stat >= thr) {
        if (above_since_[k] < 0.0) {
          above_since_[k] = t;
          type_restarted_[k] = false;
        }
        // A speed record begins where the channel was last quiet, below a quarter of the threshold. Where the
        // estimate's noise reaches that level (the 2 MW turbine's generator speed at 6 m/s: -0.2 to -0.9
        // rad/s against 0.45) it holds a second of healthy samples before the onset. The reading's step at
        // the onset then moves with the error's: the full model fits it (misfit 6255 in 22 blocks) and both
        // others fail, by amounts that decide nothing (a gain of 0.926 named an offset, "evidence 488",
        // 1.2 s after its onset; multi-fault suite set 173 scenario 08). Such a record starts again, from
        // samples after the onset only.
        if (c < 2 && cfg_.type_misfit_max > 0.0 && !type_restarted_[k] &&
            fault_type_[k].misfit() >= cfg_.type_misfit_max) {
          fault_type_[k].restart();
          type_restarted_[k] = true;
        }
        const char* fault =
            t - above_since_[k] >= cfg_.raise_time - 1e-9 ? fault_class(k, t - above_since_[k]) : nullptr;
        if (fault) {
          mark_raised(fault);
          // Detected when it could be acted on: the wait for the type counts as detection delay.
          event(true, std::max(above_since_[k], t - cfg_.raise_time));
        }
      } else {
        above_since_[k] = -1.0;
      }
    } else {
      // A gain shows only where the quantity is large (a pitch gain at fine pitch is no error at all): a
      // raised gain clears only where it would still be seen.
      const bool gain_hidden = std::strcmp(raised_class_[k], "sensor_gain") == 0 &&
                               std::fabs(raised_gain_[k] - 1.0) * std::fabs(out_.corrected[k]) < thr;
      // A reading still repeated to the last bit at the value it stuck at is still stuck, whatever the
      // estimate says: the rotor-speed sensor sticking 93 s into the generator's fault took the observer's
      // estimate onto the stuck reading, the generator's was cleared 15 s before its end (multi-fault suite
      // seed 69), and drive_train's energy balance took those seconds of a frozen speed as healthy and raised
      // a false efficiency_loss.
      const bool raised_stuck = std::strcmp(raised_class_[k], "sensor_stuck") == 0;
      const bool still_stuck = raised_stuck && reading_stuck(k) && last_reading_[k] == raised_reading_[k];
      // A raised offset or gain whose reading then sticks to the last bit is a second fault of the sensor:
      // its report is the stuck one from then on (a generator-speed gain whose reading stuck 7 s after it
      // ended was never named stuck: its gain report stood 160 s longer; fault suite set 427, scenario 03).
      if (cfg_.stuck_after_raise && !raised_stuck && reading_stuck(k) && stat >= thr) {
        event(false, t);
        mark_raised("sensor_stuck");
        event(true, t);
        continue;
      }
      if (stat < cfg_.clear_ratio * thr && !gain_hidden && !still_stuck) {
        if (below_since_[k] < 0.0) below_since_[k] = t;
        if (t - below_since_[k] >= cfg_.clear_time - 1e-9) {
          raised_[k] = false;
          above_since_[k] = -1.0;
          event(false, below_since_[k]);
        }
      } else {
        below_since_[k] = -1.0;
      }
    }
  }
}

}  // namespace windfdi::sensor_bias
