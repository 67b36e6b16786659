// Blade-root moment sensor monitoring (Stotsky 2014), per sample: input validity, the two estimators of each
// blade, the gate, the revolution and the estimate rate at which the tests and the adaptation run.
#include "blade_load_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace windfdi::blade_load {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;
}  // namespace

BladeLoadMonitor::BladeLoadMonitor(const MonitorConfig& config, LoadTable table)
    : cfg_(config),
      table_(std::move(table)),
      lidar_(config.model, &table_),
      validity_(config.validity),
      suspects_(config.suspect_inputs, config.harmonic.dt),
      gate_(config.gate, config.harmonic.dt),
      lull_(config.lull),
      tests_(config.detection, config.learning, config.episode),
      adaptation_(config.adaptation) {
  for (int b = 0; b < 3; ++b) {
    sensor_[b] = std::make_unique<HarmonicEstimator>(cfg_.harmonic);
    model_[b] = std::make_unique<HarmonicEstimator>(cfg_.harmonic);
  }
}

bool BladeLoadMonitor::learned() const {
  for (int c = 0; c < kChannels; ++c)
    if (!tests_.healthy().learned(c)) return false;
  return true;
}

void BladeLoadMonitor::reset_windows() {
  for (int b = 0; b < 3; ++b) {
    sensor_[b]->reset();
    model_[b]->reset();
    est_.sensor_valid[b] = est_.model_valid[b] = false;
  }
  last_azimuth_ = kNaN;
  rev_angle_ = 0.0;
  adaptation_.restart();
}

bool BladeLoadMonitor::gated() const {
  uint64_t n = 0;
  for (const auto& e : sensor_) n = std::max<uint64_t>(n, static_cast<uint64_t>(e->size()));
  for (const auto& e : model_) n = std::max<uint64_t>(n, static_cast<uint64_t>(e->size()));
  return gate_.holds(n);
}

bool BladeLoadMonitor::update(const FrameSample& sample, bool gap, std::vector<FaultEvent>& events) {
  // A rotor-speed fault another service has placed: lambda and the revolutions from the generator speed.
  FrameSample twin;
  const FrameSample& s = suspects_.speed_twin(sample, twin) ? twin : sample;
  const double t = s.t;
  // Lost samples leave a hole in the LIDAR history as long as the gap: a frozen service or plant raised
  // lidar sensor_invalid on every turbine when it resumed (the reliability campaign).
  const double lidar_grace = lidar_.delay() + cfg_.model.max_lidar_age;
  // A short hole leaves the gauge windows running: they fit the harmonics by azimuth, so a few missing
  // samples cost a few samples' weight. Restarting them on every hole, 20 samples lost every 5 s kept the
  // windows refilling most of the time and delayed a drift by 19 s. The LIDAR model's windows restart by
  // themselves where the hole reaches the delayed LIDAR values (below).
  const bool short_gap = gap && bridgeable_hole(last_sequence_, last_t_, s.sequence, t, cfg_.max_bridged_gap);
  last_t_ = t;
  last_sequence_ = s.sequence;
  if (gap && !short_gap) reset_windows();
  // LIDAR frames lost on the way leave the same hole in its history, with the samples whole.
  if (gap || s.lidar_lost_on_the_way) validity_.restart_lidar(t, lidar_grace);
  // The LIDAR history is kept through a standstill: resuming with a stale one read as a lost LIDAR.
  if ((s.valid_mask & kValidLidar) && lidar_.add_lidar(t, s.lidar_v_upper, s.lidar_v_lower))
    validity_.restart_lidar(t, lidar_grace);
  const bool speed_ok =
      std::isfinite(s.rotor_speed) && (s.valid_mask & kValidRotorSpeed) && s.rotor_speed <= 5.0;
  if (!speed_ok || !std::isfinite(s.azimuth) || !(s.valid_mask & kValidAzimuth) ||
      s.rotor_speed < cfg_.min_rotor_speed) {
    ++rejected_;
    if (sensor_[0]->size() > 0) reset_windows();
    return false;
  }
  if (next_tick_ < 0) next_tick_ = t;

  // Blade moments: a gauge raised sensor_invalid now restarts its window.
  std::array<bool, 3> lost{};
  const std::array<bool, 3> m_ok = validity_.moments(s, events, lost);
  for (int b = 0; b < 3; ++b)
    if (lost[b]) {
      sensor_[b]->reset();
      est_.sensor_valid[b] = false;
    }

  // LIDAR: the model needs the value measured D / V ago (added above).
  const std::array<double, 3> pitch = validity_.pitch(s);
  std::array<double, 3> mm{};
  const bool model_ok = lidar_.moments(t, s.rotor_speed, s.azimuth, pitch, mm);
  // Steep-surface gate on the low-passed pitch (lambda of the last delayed LIDAR value; none before the
  // first), closed too while an input of the model is suspect.
  gate_.update(table_, lidar_.lambda(), pitch, suspects_.update(s));
  if (model_ok) {
    adaptation_.add_sample(lidar_.shear(), lidar_.lambda(), (pitch[0] + pitch[1] + pitch[2]) / 3.0);
  } else if (model_[0]->size() > 0) {
    // The model's windows stay whole, as the gauges' do: lost samples restart both, but the delayed LIDAR
    // values fall in the hole for a while after, and a model window across it averaged each blade over
    // other azimuths than its gauge window did. The cross-blade mean ratio then raised false steps on
    // healthy gauges of a service that had lost 3 s of samples (a starved CI machine).
    for (auto& m : model_) m->reset();
    est_.model_valid = {false, false, false};
  }
  if (validity_.lidar(t, model_ok, events)) {
    // Fall back to sensor-only (cross-blade) monitoring until the LIDAR is back.
    for (auto& m : model_) m->reset();
    est_.model_valid = {false, false, false};
  }

  for (int b = 0; b < 3; ++b) {
    const double psi = s.azimuth + b * kTwoPi / 3.0;
    if (m_ok[b]) sensor_[b]->update(s.blade_moment[b], psi, s.rotor_speed);
    if (model_ok) model_[b]->update(mm[b], psi, s.rotor_speed);
  }

  // One revolution of blade 1 since the last per-revolution evaluation?
  bool rev = false;
  if (std::isfinite(last_azimuth_)) {
    rev_angle_ += std::max(0.0, std::remainder(s.azimuth - last_azimuth_, kTwoPi));
    if (rev_angle_ >= kTwoPi) {
      rev_angle_ -= kTwoPi;
      rev = true;
    }
  }
  last_azimuth_ = s.azimuth;
  const bool tick_due = t >= next_tick_ - 1e-9;
  if (rev || tick_due) {
    for (int b = 0; b < 3; ++b) {
      est_.sensor_valid[b] = m_ok[b] && sensor_[b]->solve().valid;
      est_.a_sensor[b] = sensor_[b]->amplitude();
      est_.mean_sensor[b] = sensor_[b]->window_mean();
      est_.model_valid[b] = validity_.lidar_ok() && model_ok && model_[b]->solve().valid;
      est_.a_model[b] = model_[b]->amplitude();
      est_.mean_model[b] = model_[b]->window_mean();
    }
  }
  const bool held = gated();
  if (rev) revolution(t, held);
  if (tick_due) {
    while (next_tick_ <= t + 1e-9) next_tick_ += 1.0 / cfg_.estimate_rate;
    // A lull holds the outlier test only: the per-revolution learning, noise level and drift test see it as
    // before (holding those too shifted the table adaptation and the noise level, and the blades' reports
    // on a pitch-sensor bias came 3 in 3 suite seeds more often).
    tick(t, held || lull_.holds(window_load(est_)), events);
  }
  return true;
}

void BladeLoadMonitor::revolution(double t, bool held) {
  if (last_rev_t_ >= 0) rev_time_ = t - last_rev_t_;
  last_rev_t_ = t;
  // A window with a blade on the steep part of k_M, or a suspect input: no information.
  const BladeChannels x = held ? unavailable_channels() : residual_channels(est_);
  last_x_ = x;
  if (held) ++gated_revolutions_;
  const double load = window_load(est_);
  if (lull_.holds(load)) ++lull_revolutions_;
  lull_.follow(load, rev_time_);
  tests_.revolution(t, rev_time_, x, validity_.lidar_ok());
  // Not on a window the gate holds: a suspect speed or pitch (a biased lambda) taught the table a wrong k_M,
  // and false alarms on healthy gauges followed once the fault was gone.
  bool healthy =
      validity_.lidar_ok() && tests_.healthy().learned(kMeanChannel) && !tests_.any_raised() && !held;
  for (int b = 0; b < 3; ++b)
    healthy = healthy && est_.sensor_valid[b] && est_.model_valid[b] && !tests_.exceeding(b);
  adaptation_.revolution(healthy, est_.mean_sensor, est_.mean_model, table_);
}

void BladeLoadMonitor::tick(double t, bool held, std::vector<FaultEvent>& events) {
  out_.t = t;
  out_.lidar_ok = validity_.lidar_ok();
  out_.shear = validity_.lidar_ok() ? lidar_.shear() : kNaN;
  for (int b = 0; b < 3; ++b) {
    out_.valid[b] = est_.sensor_valid[b];
    out_.a1_sensor[b] = est_.sensor_valid[b] ? est_.a_sensor[b] : kNaN;
    out_.a1_model[b] = est_.model_valid[b] ? est_.a_model[b] : kNaN;
    out_.delta_a[b] = est_.sensor_valid[b] && est_.model_valid[b] ? est_.a_model[b] - est_.a_sensor[b] : kNaN;
  }
  due_ = true;
  if (held) {
    // No information in this window: no run continues through it, and an episode is held as it is.
    tests_.hold();
    return;
  }
  tests_.tick(t, rev_time_, residual_channels(est_), est_, validity_.lidar_ok(), events);
}

bool BladeLoadMonitor::estimate_due(BladeLoadOutput& out) {
  if (!due_) return false;
  due_ = false;
  out = out_;
  return true;
}

MonitorState BladeLoadMonitor::state() const {
  MonitorState s;
  s.table_factors = table_.factors();
  s.n_lambda = table_.n_lambda();
  s.n_pitch = table_.n_pitch();
  s.healthy = tests_.healthy().stats();
  return s;
}

void BladeLoadMonitor::restore(const MonitorState& s) {
  if (s.n_lambda == table_.n_lambda() && s.n_pitch == table_.n_pitch() &&
      s.table_factors.size() == table_.factors().size())
    table_.factors() = s.table_factors;
  tests_.restore(s.healthy);
}

}  // namespace windfdi::blade_load
