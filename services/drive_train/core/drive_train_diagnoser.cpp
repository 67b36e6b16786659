// One turbine's converter and drive-train diagnosis.
#include "drive_train_diagnoser.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace windfdi::drive_train {

namespace {
/// The blades' mean pitch (deg): what each energy-balance block keeps of the pitch.
double mean_pitch(const FrameSample& s) {
  double pitch = 0.0;
  for (std::size_t i = 0; i < kBlades; ++i) pitch += s.pitch[i] / kBlades;
  return pitch;
}
}  // namespace

DiagnoserConfig load_diagnoser_config(const YamlSection& s, const TurbineParams& turbine) {
  // clang-format off
  s.require_known_keys({"turbine_file", "estimate_rate", "wind_window", "min_offset", "cusum_threshold",
                        "noise_learn_time", "noise_floor", "witness_ratio", "offset_clear_time",
                        "block_time", "test_time", "reference_gap", "reference_time", "efficiency_step",
                        "efficiency_clear_ratio", "efficiency_clear_time", "efficiency_confirm_time", "min_power_share", "max_pitch_wind",
                        "min_generator_speed", "min_generator_speed_share", "max_torque", "max_generator_speed", "max_power",
                        "sample_time", "iced_inertia_ratio", "efficiency_step_shape", "iced_step_share", "step_shape_parsimony", "efficiency_noise_sigmas", "speed_pair_mismatch", "speed_pair_time", "inertia_ratio_floor", "context_lookback",
                        "max_bridged_gap", "rotor_speed_fallback", "rotor_speed_noise_sigmas", "rotor_speed_noise_time",
                        "rotor_speed_noise_min_time"});
  // clang-format on
  DiagnoserConfig c;
  c.sample_time = s.get_number("sample_time", c.sample_time, 1e-4, 1.0);
  ConverterConfig& v = c.converter;
  v.time_constant = turbine.converter_time_constant;
  v.generator_efficiency = turbine.generator_efficiency;
  v.min_offset = s.get_number("min_offset", v.min_offset, 1.0, 1e5);
  v.cusum_threshold = s.get_number("cusum_threshold", v.cusum_threshold, 1.0, 100.0);
  v.noise_learn_time = s.get_number("noise_learn_time", v.noise_learn_time, 1.0, 3600.0);
  v.noise_floor = s.get_number("noise_floor", v.noise_floor, 0.001, 1e4);
  v.witness_ratio = s.get_number("witness_ratio", v.witness_ratio, 0.01, 1.0);
  v.clear_time = s.get_number("offset_clear_time", v.clear_time, 0.0, 600.0);
  EfficiencyConfig& e = c.efficiency;
  e.gear_ratio = turbine.gear_ratio;
  c.fixed_pitch = turbine.fixed_pitch;
  e.rotor_inertia = turbine.rotor_inertia;
  e.generator_inertia = turbine.generator_inertia;
  e.rotor_friction = turbine.rotor_friction;
  e.generator_friction = turbine.generator_friction;
  e.rated_power = turbine.rated_power;
  e.block_time = s.get_number("block_time", e.block_time, 1.0, 600.0);
  e.test_time = s.get_number("test_time", e.test_time, e.block_time, 3600.0);
  e.reference_gap = s.get_number("reference_gap", e.reference_gap, 0.0, 3600.0);
  e.reference_time = s.get_number("reference_time", e.reference_time, e.block_time, 36000.0);
  e.step = s.get_number("efficiency_step", e.step, 0.001, 0.5);
  e.clear_ratio = s.get_number("efficiency_clear_ratio", e.clear_ratio, 0.0, 1.0);
  e.clear_time = s.get_number("efficiency_clear_time", e.clear_time, 0.0, 3600.0);
  e.confirm_time = s.get_number("efficiency_confirm_time", e.confirm_time, 0.0, 600.0);
  e.min_power_share = s.get_number("min_power_share", e.min_power_share, 0.0, 1.0);
  c.max_pitch_wind = s.get_number("max_pitch_wind", c.max_pitch_wind, 3.0, 60.0);
  e.max_pitch = feathering_pitch(turbine, c.max_pitch_wind);
  // A share of the turbine's rated generator speed (min_generator_speed, rad/s, overrides it): the
  // benchmark's 30 rad/s would leave a medium-speed drive train (52 rad/s rated) little but rated wind.
  e.min_generator_speed =
      s.get_number("min_generator_speed",
                   s.get_number("min_generator_speed_share", 0.185, 0.0, 1.0) * turbine.rated_generator_speed,
                   0.0, 1000.0);
  e.iced_inertia_ratio = s.get_number("iced_inertia_ratio", e.iced_inertia_ratio, 1.0, 10.0);
  e.step_shape = s.get<bool>("efficiency_step_shape", e.step_shape);
  e.iced_step_share = s.get_number("iced_step_share", e.iced_step_share, 0.0, 1.0);
  e.step_shape_parsimony = s.get<bool>("step_shape_parsimony", e.step_shape_parsimony);
  e.noise_sigmas = s.get_number("efficiency_noise_sigmas", e.noise_sigmas, 0.0, 100.0);
  c.speed_pair_mismatch = s.get_number("speed_pair_mismatch", c.speed_pair_mismatch, 0.0, 1.0);
  c.speed_pair_time = s.get_number("speed_pair_time", c.speed_pair_time, 0.1, 60.0);
  c.rotor_speed_fallback = s.get<bool>("rotor_speed_fallback", c.rotor_speed_fallback);
  c.rotor_speed_noise_sigmas =
      s.get_number("rotor_speed_noise_sigmas", c.rotor_speed_noise_sigmas, 0.0, 20.0);
  c.rotor_speed_noise_time =
      s.get_number("rotor_speed_noise_time", c.rotor_speed_noise_time, e.block_time, 1e6);
  c.rotor_speed_noise_min_time =
      s.get_number("rotor_speed_noise_min_time", c.rotor_speed_noise_min_time, e.block_time, 1e6);
  e.inertia_ratio_floor = s.get_number("inertia_ratio_floor", e.inertia_ratio_floor, 0.0, 1.0);
  v.min_generator_speed = e.min_generator_speed;
  c.estimate_rate = s.get_number("estimate_rate", c.estimate_rate, 0.01, 100.0);
  c.wind_window = s.get_number("wind_window", c.wind_window, 0.0, 60.0);
  c.context_lookback = s.get_number("context_lookback", c.context_lookback, 0.0, 3600.0);
  c.max_bridged_gap = s.get_number("max_bridged_gap", c.max_bridged_gap, 0.0, 10.0);
  // Plausible ranges are multiples of the turbine's rated values (the benchmark's 2e5 N m, 400 rad/s and 2e7
  // W there): a 15 MW medium-speed generator's rated torque, 0.3 MN m, was beyond the fixed 2e5 N m.
  c.max_torque = s.get_number("max_torque", 6.6 * turbine.rated_generator_torque(), 1.0, 1e9);
  c.max_generator_speed = s.get_number("max_generator_speed", 2.47 * turbine.rated_generator_speed, 1.0, 1e4);
  c.max_power = s.get_number("max_power", 4.17 * turbine.rated_power, 1.0, 1e10);
  return c;
}

DriveTrainDiagnoser::DriveTrainDiagnoser(const DiagnoserConfig& config, const AeroModel& aero)
    : c_(config),
      converter_(config.converter, config.sample_time),
      balance_(config, aero, config.efficiency),
      rotor_shadow_(config, aero, [&] {
        EfficiencyConfig e = config.efficiency;
        e.step = 1.0;  // it learns; it never raises (a raised test freezes its reference)
        return e;
      }()) {
  rotor_shadow_.power.set_speed_average(true);
}

double DriveTrainDiagnoser::rotor_speed_drop_rms() const {
  const double min_blocks = c_.rotor_speed_noise_min_time / c_.efficiency.block_time;
  return shadow_blocks_ + 1e-9 >= min_blocks ? std::sqrt(shadow_drop_square_) : 0.0;
}

void DriveTrainDiagnoser::update_step() {
  double step = c_.efficiency.step;
  if (on_rotor_speed(context_) && c_.rotor_speed_noise_sigmas > 0.0) {
    // Its noise not learned yet (a generator-speed fault within minutes of a start), the fallback's
    // balance runs and judges nothing.
    const double rms = rotor_speed_drop_rms();
    step = rms > 0.0 ? std::max(step, c_.rotor_speed_noise_sigmas * rms)
                     : std::numeric_limits<double>::infinity();
  }
  balance_.monitor.set_step(step);
}

void DriveTrainDiagnoser::set_context(const InputContext& context, double) {
  const bool was_on_rotor = on_rotor_speed(context_);
  // A sensor newly suspect was wrong before it was reported: the newest blocks may hold its error. Unless the
  // speed pair already dropped them when the two speeds began to disagree and has held the balance since
  // (dropped twice, a minute more of blocks had to be made again before the test could judge).
  bool newly_suspect =
      context.generator_speed_suspect && !context_.generator_speed_suspect && !speeds_disagree_;
  newly_suspect =
      newly_suspect || (was_on_rotor && context.rotor_speed_suspect && !context_.rotor_speed_suspect);
  for (std::size_t i = 0; i < kBlades; ++i)
    newly_suspect = newly_suspect || (context.pitch_sensor_suspect[i] && !context_.pitch_sensor_suspect[i]);
  if (newly_suspect) balance_.monitor.discard_recent(c_.context_lookback);
  if (was_on_rotor != on_rotor_speed(context)) source_switch_t_ = t_;
  context_ = context;
  balance_.power.set_absent(context.absent, c_.fixed_pitch);
  balance_.power.set_speed_average(on_rotor_speed(context));
  rotor_shadow_.power.set_absent(context.absent, c_.fixed_pitch);
  update_step();
}

bool DriveTrainDiagnoser::update(const FrameSample& s, bool gap, std::vector<FaultEvent>& events) {
  t_ = s.t;
  const auto plausible_speed = [&](double w) {
    return std::isfinite(w) && w >= 0.0 && w <= c_.max_generator_speed;
  };
  const bool torques = std::isfinite(s.gen_torque) && std::fabs(s.gen_torque) <= c_.max_torque &&
                       std::isfinite(s.gen_torque_ref) && std::fabs(s.gen_torque_ref) <= c_.max_torque;
  const bool plausible = torques && plausible_speed(s.generator_speed);
  // The power only witnesses: an implausible one is left out, the sample is kept.
  const double power = std::isfinite(s.power) && std::fabs(s.power) <= c_.max_power ? s.power : kNaN;
  const bool after_gap = gap || last_rejected_;
  last_rejected_ = !plausible;
  if (!plausible) {
    ++rejected_;
  } else {
    converter_.update(s.gen_torque, s.gen_torque_ref, s.generator_speed, power,
                      !context_.generator_speed_suspect, after_gap);
    report_converter(s.t, events);
  }

  // The two speed sensors against each other: the balance takes omega_g, which a sensor fault moves before
  // sensor_bias names it. While they disagree with neither reported, no block is made, and those of the last
  // context_lookback are dropped when they begin to.
  const bool placed = context_.rotor_speed_suspect || context_.generator_speed_suspect;
  if (c_.speed_pair_mismatch > 0.0 && plausible && std::isfinite(s.rotor_speed) && s.rotor_speed >= 0.0 &&
      (s.valid_mask & kValidRotorSpeed) && !placed) {
    pair_rotor_.add(s.rotor_speed);
    pair_generator_.add(s.generator_speed);
    if (static_cast<double>(pair_rotor_.n) * c_.sample_time >= c_.speed_pair_time - 1e-9) {
      const double rotor = pair_rotor_.mean(), generator = pair_generator_.mean() / c_.efficiency.gear_ratio;
      const bool disagree = rotor * c_.efficiency.gear_ratio > c_.efficiency.min_generator_speed &&
                            std::fabs(generator - rotor) > c_.speed_pair_mismatch * rotor;
      if (disagree && !speeds_disagree_) {
        balance_.monitor.discard_recent(c_.context_lookback);
        ++disagreements_;
      }
      speeds_disagree_ = disagree;
      pair_rotor_.reset(), pair_generator_.reset();
    }
  } else if (placed || c_.speed_pair_mismatch <= 0.0) {
    speeds_disagree_ = false;
    pair_rotor_.reset(), pair_generator_.reset();
  }

  // The energy balance judges each sample half an anemometer window late, with the rotor speed taken as
  // omega_g / N (the power model's tip-speed ratio then carries the generator sensor's small noise). A
  // suspect pitch reading is replaced by its reference (the actuator follows it): the balance goes on through
  // a pitch sensor's fault. Through a generator-speed sensor's fault it takes the rotor's sensor times N,
  // averaged below: over healthy hours on it the drop's scatter stays inside the step (unit test
  // OnTheRotorsSpeedSensorHealthyHoursRaiseNothing).
  const bool on_rotor = on_rotor_speed(context_);
  const double rotor_reading = (s.valid_mask & kValidRotorSpeed) ? s.rotor_speed : kNaN;
  const double balance_speed = on_rotor ? rotor_reading * c_.efficiency.gear_ratio : s.generator_speed;
  const bool balanced = torques && plausible_speed(balance_speed);
  FrameSample fed = s;
  for (std::size_t i = 0; i < kBlades; ++i)
    if (context_.pitch_sensor_suspect[i]) fed.pitch[i] = s.pitch_ref[i];
  fed.rotor_speed = balanced ? balance_speed / c_.efficiency.gear_ratio : kNaN;
  fed.aero_power = kNaN;  // the model's power, never a recording's column: the balance tests the model
  FrameSample centre;
  double aero_power = kNaN;
  bool broken = false;
  uint64_t lost = 0;
  if (centre_sample(balance_, fed, gap || !balanced, centre, aero_power, broken, lost)) {
    // The rotor's sensor is averaged over the wind window (centred): its noise, 50 times the generator's
    // divided by N, read at the blocks' 0.5 s ends put 4 % rms into the drop at 6 m/s. No block spans a
    // change of sensor: the samples whose window holds both are left out.
    if (on_rotor) centre.generator_speed = centre.rotor_speed * c_.efficiency.gear_ratio;
    const bool switching = centre.t <= source_switch_t_ + 0.5 * c_.wind_window + 1e-9;
    if (!switching) source_switch_t_ = kNaN;
    const bool forget = context_.generator_speed_suspect && !on_rotor;
    const bool usable = !forget && !speeds_disagree_ && !switching && !broken && !context_.turbine_stopped &&
                        std::isfinite(centre.rotor_speed);
    balance_.monitor.update(centre.gen_torque, centre.generator_speed, aero_power, mean_pitch(centre), usable,
                            forget, static_cast<std::size_t>(lost));
    report_efficiency(centre.t, events);
  }
  update_rotor_shadow(fed, rotor_reading, gap, torques && !placed && !speeds_disagree_ && !on_rotor);
  return plausible;
}

namespace {
/// A warning of this service on `component`, raised or cleared at t; `since` keeps the time it was raised.
FaultEvent warning(double t, const char* component, const char* fault, bool raised, double& since) {
  FaultEvent e;
  e.t = t;
  e.source = "drive_train";
  e.component = component;
  e.fault = fault;
  e.raised = raised;
  e.severity = "warning";
  if (raised) since = t;
  e.t_detected = since;
  return e;
}
}  // namespace

bool DriveTrainDiagnoser::centre_sample(Balance& b, const FrameSample& fed, bool gap, FrameSample& centre,
                                        double& aero_power, bool& broken, uint64_t& lost) const {
  bool centre_gap = false;
  if (!b.power.push(fed, gap, centre, centre_gap, aero_power)) return false;
  // A short hole of lost samples leaves the block running with its span counted (ending the block on
  // each, 20 samples lost every few seconds let no 5 s block ever close).
  const bool bridged = centre_gap && bridgeable_hole(b.last_centre_sequence, b.last_centre_t, centre.sequence,
                                                     centre.t, c_.max_bridged_gap);
  lost = bridged ? samples_lost(b.last_centre_sequence, centre.sequence) : 0;
  broken = centre_gap && !bridged;
  b.last_centre_t = centre.t;
  b.last_centre_sequence = centre.sequence;
  return true;
}

void DriveTrainDiagnoser::update_rotor_shadow(FrameSample fed, double rotor, bool gap, bool speeds_healthy) {
  // The rotor's sensor beside omega_g / N, each block's drop against its own reference: what the fallback's
  // test would read on this turbine in this wind, were nothing wrong. Fed only while both sensors agree and
  // neither is reported, so that a speed fault teaches it nothing.
  if (c_.rotor_speed_noise_sigmas <= 0.0) return;
  const bool ok = speeds_healthy && std::isfinite(rotor) && rotor >= 0.0 &&
                  rotor * c_.efficiency.gear_ratio <= c_.max_generator_speed;
  fed.rotor_speed = ok ? rotor : kNaN;
  FrameSample centre;
  double aero_power = kNaN;
  bool broken = false;
  uint64_t lost = 0;
  if (!centre_sample(rotor_shadow_, fed, gap || !ok, centre, aero_power, broken, lost)) return;
  const bool usable = !broken && !context_.turbine_stopped && std::isfinite(centre.rotor_speed);
  const EfficiencyState& st = rotor_shadow_.monitor.update(
      centre.gen_torque, centre.rotor_speed * c_.efficiency.gear_ratio, aero_power, mean_pitch(centre),
      usable, !ok, static_cast<std::size_t>(lost));
  if (st.tests == shadow_tests_seen_) return;
  shadow_tests_seen_ = st.tests;
  // What the rotor's sensor adds: its drop less the generator's balance's, which a real loss moves alike
  // (learned on its own drop, an efficiency loss 20 minutes before raised the fallback's step to 6.7 % and a
  // second loss inside a generator-speed fault went unseen until the fault ended, tuning set 152).
  const EfficiencyState& main = balance_.monitor.state();
  if (!main.ready || main.raised) return;
  const double extra = st.drop - main.drop;
  const double memory = c_.rotor_speed_noise_time / c_.efficiency.block_time;
  shadow_blocks_ = std::min(shadow_blocks_ + 1.0, memory);
  shadow_drop_square_ += (extra * extra - shadow_drop_square_) / shadow_blocks_;
  update_step();
}

void DriveTrainDiagnoser::report_converter(double t, std::vector<FaultEvent>& events) {
  const ConverterState& st = converter_.state();
  if (!st.changed) return;
  FaultEvent e = warning(t, "converter", "torque_offset", st.raised, converter_since_);
  e.statistic = st.statistic;
  e.threshold = c_.converter.cusum_threshold;
  e.size = st.offset;
  std::ostringstream d;
  d << "generator torque offset " << std::lround(st.offset) << " N m (power witness "
    << std::lround(st.witness_offset) << " N m, torque noise " << std::lround(st.noise) << " N m)";
  e.detail = st.raised ? d.str() : "torque residual back within half the smallest offset";
  events.push_back(e);
}

void DriveTrainDiagnoser::report_efficiency(double t, std::vector<FaultEvent>& events) {
  const EfficiencyState& st = balance_.monitor.state();
  if (!st.changed) return;
  FaultEvent e = warning(t, "drive_train", "efficiency_loss", st.raised, efficiency_since_);
  e.statistic = st.drop;
  e.threshold = balance_.monitor.step();
  e.size = st.drop;
  std::ostringstream d;
  d.precision(3);
  d << "drive-train efficiency " << st.efficiency << " against " << st.reference << " before (drop "
    << 100.0 * st.drop << " %";
  if (st.raised) d << ", standard error " << 100.0 * st.standard_error << " %";
  d << ")";
  e.detail = d.str();
  events.push_back(e);
}

bool DriveTrainDiagnoser::estimate_due(DriveTrainOutput& out) {
  if (have_estimate_ && t_ + 1e-9 < next_estimate_) return false;
  have_estimate_ = true;
  next_estimate_ = t_ + 1.0 / c_.estimate_rate;
  const ConverterState& cv = converter_.state();
  const EfficiencyState& ef = balance_.monitor.state();
  out.t = t_;
  out.torque_offset = cv.raised ? cv.offset : cv.residual_mean;
  out.torque_statistic = cv.statistic;
  out.efficiency = ef.ready ? ef.efficiency : kNaN;
  out.efficiency_reference = ef.ready ? ef.reference : kNaN;
  return true;
}

}  // namespace windfdi::drive_train
