// The baseline controller (plant_sim/README.md "Controller").
#include "baseline_controller.hpp"

#include <algorithm>
#include <cmath>

#include "lidar_shear.hpp"

namespace windfdi::plant {

BaselineController::BaselineController(const TurbineParams& turbine, const ControllerParams& params,
                                       double lidar_distance, double fallback_wind, double dt)
    : p_(turbine),
      aero_(turbine),
      ctl_(params),
      lidar_distance_(lidar_distance),
      fallback_wind_(fallback_wind),
      dt_(dt) {
  // The pitch gains were tuned on the benchmark turbine. The speed loop's dynamics are kept on another
  // turbine by scaling them with J omega / P: the lumped inertia it accelerates, over the torque a degree of
  // pitch moves at rated speed (which scales with P / omega). 1 on the benchmark turbine.
  const TurbineParams bench;
  const auto loop = [](const TurbineParams& t) {
    return t.lumped_inertia() * t.rated_generator_speed / t.rated_power;
  };
  pitch_gain_scale_ = loop(p_) / loop(bench);
}

void BaselineController::start_at(double pitch, double generator_speed) {
  pitch_ref_ = {pitch, pitch, pitch};
  pitch_integral_ = pitch;
  speed_filtered_ = generator_speed;
}

ControllerOutput BaselineController::step(double t, const ControlInput& in, const FrameSample& m,
                                          bool lidar_updated, double converter_torque) {
  if (lidar_updated) {
    lidar_upper_ = m.lidar_v_upper;
    lidar_lower_ = m.lidar_v_lower;
    lidar_history_.push_back({t, m.lidar_v_upper, m.lidar_v_lower});
    while (lidar_history_.size() > 200) lidar_history_.pop_front();
  }
  ControllerOutput out;
  double wg = (in.use_corrected_generator_speed && std::isfinite(in.corrected_generator_speed))
                  ? in.corrected_generator_speed
                  : m.generator_speed;
  if (!std::isfinite(wg)) wg = speed_filtered_;  // an invalid sample: hold the last filtered value
  speed_filtered_ += (wg - speed_filtered_) * dt_ / (ctl_.speed_filter + dt_);

  if (in.mode == OperatingMode::kSafeStop) {
    // Feather at the rate limit; the torque decays with the converter's torque (time constant
    // stop_torque_time) and 1 N m per sample, so the rotor is not braked hard while the blades feather.
    if (stop_torque_ < 0) stop_torque_ = converter_torque;
    stop_torque_ = std::max(0.0, stop_torque_ - converter_torque / ctl_.stop_torque_time * dt_ - 1.0);
    out.torque_ref = stop_torque_;
    out.pitch_ref = {p_.pitch_max, p_.pitch_max, p_.pitch_max};
    pitch_integral_ = p_.pitch_max;
    pitch_ref_ = derated(out.pitch_ref, in);
    out.pitch_ref = pitch_ref_;
    return out;
  }
  stop_torque_ = -1;
  const bool degraded = in.mode == OperatingMode::kDegraded;
  const double omega_ref = p_.rated_generator_speed * (degraded ? ctl_.degraded_speed : 1.0);
  const double power_share = degraded ? ctl_.degraded_power : 1.0;
  const double torque_max = p_.rated_power * power_share / (p_.generator_efficiency * omega_ref);
  // Region 2: K omega^2 from Cp's maximum, referred to the generator side.
  static const double lambda_opt = AeroModel::optimal_tip_speed_ratio();
  static const double cp_max = AeroModel::power_coefficient(lambda_opt, 0.0);
  const double k_opt = 0.5 * p_.air_density * p_.rotor_area() * std::pow(p_.rotor_radius, 3) * cp_max /
                       std::pow(lambda_opt, 3) / std::pow(p_.gear_ratio, 3);
  // The command the converter gets: the arbiter takes a converter's estimated offset off it.
  out.torque_ref = std::min(k_opt * speed_filtered_ * speed_filtered_, torque_max) - in.torque_compensation;

  // Region 3: gain-scheduled PI on generator speed; gains scale with the (iced) inertia when adapted.
  const double inertia_scale = in.inertia > 0.0 ? in.inertia / p_.lumped_inertia() : 1.0;
  const double beta_c = std::max(0.0, pitch_integral_);
  const double gs = pitch_gain_scale_ * inertia_scale / (1.0 + beta_c / ctl_.gain_schedule_pitch);
  const double e = speed_filtered_ - omega_ref;
  pitch_integral_ = std::clamp(pitch_integral_ + ctl_.pitch_ki * gs * e * dt_, 0.0, p_.pitch_max);
  const double collective = std::clamp(pitch_integral_ + ctl_.pitch_kp * gs * e, 0.0, p_.pitch_max);

  // IPC on the 1P load (Coleman d-q).
  const bool ipc_on = in.ipc_source != IpcSource::kOff && collective > 1.0;
  std::array<double, 3> moment{};
  const bool moments_ok = ipc_moments(t, in, m, moment);
  const double psi1 = m.azimuth;
  if (ipc_on && moments_ok) {
    double md = 0, mq = 0;
    for (int i = 0; i < 3; ++i) {
      const double psi = psi1 + i * 2.0 * M_PI / 3.0;
      md += 2.0 / 3.0 * moment[i] * std::cos(psi);
      mq += 2.0 / 3.0 * moment[i] * std::sin(psi);
    }
    ipc_d_ = std::clamp(ipc_d_ + ctl_.ipc_gain * md * dt_, -ctl_.ipc_limit, ctl_.ipc_limit);
    ipc_q_ = std::clamp(ipc_q_ + ctl_.ipc_gain * mq * dt_, -ctl_.ipc_limit, ctl_.ipc_limit);
  } else {
    const double decay = std::exp(-dt_ / 2.0);  // fade out over about 2 s
    ipc_d_ *= decay;
    ipc_q_ *= decay;
  }
  for (int i = 0; i < 3; ++i) {
    const double psi = psi1 + i * 2.0 * M_PI / 3.0;
    out.pitch_ref[i] =
        std::clamp(collective + ipc_d_ * std::cos(psi) + ipc_q_ * std::sin(psi), p_.pitch_min, p_.pitch_max);
  }
  pitch_ref_ = derated(out.pitch_ref, in);
  out.pitch_ref = pitch_ref_;
  return out;
}

std::array<double, 3> BaselineController::derated(std::array<double, 3> demand,
                                                  const ControlInput& in) const {
  // The arbiter's derate limits the controller's own demand, as a turbine controller's rate limiter does
  // (the actuator's rate limit is the hardware's): the actuator follows the demand it gets and the frames
  // report. Limited in the actuator instead, a derated blade lagged a demand the frames did not show, and a
  // service whose configuration arrived late read the lag as a pitch-sensor offset (reliability campaign,
  // pitch_diag killed at 17 m/s).
  for (std::size_t i = 0; i < 3; ++i) {
    const double step = in.pitch_rate_limit[i] * dt_;
    if (in.pitch_rate_limit[i] < p_.pitch_rate_limit)
      demand[i] = std::clamp(demand[i], pitch_ref_[i] - step, pitch_ref_[i] + step);
  }
  return demand;
}

bool BaselineController::ipc_moments(double t, const ControlInput& in, const FrameSample& m,
                                     std::array<double, 3>& moment) const {
  bool ok = true;
  if (in.ipc_source == IpcSource::kStrainGauge) {
    moment = m.blade_moment;
  } else if (in.ipc_source == IpcSource::kLidarModel) {
    // The LIDAR measurement of D / V ago is the wind at the rotor now.
    double vu = kNaN, vl = kNaN;
    const double v_est = std::isfinite(lidar_upper_) ? 0.5 * (lidar_upper_ + lidar_lower_) : fallback_wind_;
    const double want = t - lidar_distance_ / std::max(v_est, 1.0);
    for (auto it = lidar_history_.rbegin(); it != lidar_history_.rend(); ++it)
      if ((*it)[0] <= want) {
        vu = (*it)[1];
        vl = (*it)[2];
        break;
      }
    const double h = p_.hub_height;
    ok = std::isfinite(vu) && std::isfinite(vl) && vu > 0 && vl > 0;
    if (ok) {
      const ShearProfile rotor = shear_from_beams(vu, vl, h, 0.5 * p_.rotor_radius);
      const double lambda = aero_.tip_speed_ratio(rotor.hub_speed, m.rotor_speed);
      for (int i = 0; i < 3; ++i) {
        const double psi = m.azimuth + i * 2.0 * M_PI / 3.0;
        const double vi = rotor.at(h + p_.load_radius * p_.rotor_radius * std::cos(psi));
        moment[i] = aero_.moment_coefficient(lambda, pitch_ref_[i]) * vi * vi;
      }
    }
  }
  for (double x : moment) ok = ok && std::isfinite(x);
  return ok;
}

}  // namespace windfdi::plant
