// One simulated benchmark turbine (drive train: Witczak et al. eqs 31-33; pitch actuator: Wu & Li eqs 11-13
// with Table 1, and the -omega_n^2 beta term eq 34 of Witczak et al. lacks).
#include "turbine_sim.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace windfdi::plant {

namespace {

constexpr int kSubsteps = 5;           // drive train and pitch integrated at 500 Hz (RK4)
constexpr double kSettleTime = 60.0;   // s simulated before t = 0 so the recording starts settled
constexpr double kShadowWidth = 0.25;  // rad, half-width of the tower shadow around azimuth pi

struct TableSignature {
  const char* type;
  double omega_n, zeta;
};
// Wu & Li, Table 1.
constexpr TableSignature kPitchFaults[] = {
    {"pump_wear", 7.27, 0.75}, {"hydraulic_leakage", 3.42, 0.9}, {"high_air_content", 5.73, 0.45}};

double wrap_pi(double a) { return std::remainder(a, 2.0 * M_PI); }

uint64_t mix_seed(uint64_t seed, const std::string& id) {
  return seed * 0x9E3779B97F4A7C15ull ^ std::hash<std::string>{}(id);
}

}  // namespace

TurbineSim::TurbineSim(const TurbineParams& params, const TurbineScenario& turbine,
                       const std::vector<FaultSpec>& faults, uint64_t seed, double sample_rate,
                       const ControllerParams& controller, const NoiseParams& noise)
    : id_(turbine.id),
      p_(params),
      aero_(params),
      wind_(turbine.wind),
      faults_(faults),
      ctl_(controller),
      noise_(noise),
      dt_(1.0 / sample_rate),
      rng_(mix_seed(seed, turbine.id)),
      ice_mass_(turbine.ice_mass),
      ice_initial_(turbine.ice_mass),
      shed_done_(faults.size(), false),
      stuck_value_(faults.size(), 0.0),
      stuck_latched_(faults.size(), false) {
  // Frozen turbulence: what the LIDAR sees at distance D reaches the rotor D / V later.
  delay_samples_ = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::lround(wind_.lidar_distance / wind_.mean / dt_)));
  const double v = wind_.mean;
  // Start at the operating point of the mean wind.
  const double lambda_opt = AeroModel::optimal_tip_speed_ratio();
  const double omega_rated = p_.rated_generator_speed / p_.gear_ratio;
  omega_r_ = std::min(lambda_opt * v / p_.rotor_radius, omega_rated);
  double beta = 0.0;
  if (omega_r_ >= omega_rated - 1e-9) {
    double lo = 0.0, hi = 45.0;
    const double target = p_.rated_power / p_.generator_efficiency / p_.drive_train_efficiency;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (aero_.aero_power(v, omega_r_, mid) > target ? lo : hi) = mid;
    }
    beta = 0.5 * (lo + hi);
  }
  omega_g_ = omega_r_ * p_.gear_ratio;
  for (auto& a : actuator_) a.angle = beta;
  pitch_ref_ = {beta, beta, beta};
  pitch_integral_ = beta;
  speed_filtered_ = omega_g_;
  const double t_aero = aero_.aero_torque(v, omega_r_, beta);
  theta_ = (t_aero - p_.rotor_friction * omega_r_) / p_.drive_train_stiffness;
  gen_torque_ = p_.drive_train_efficiency * (t_aero - p_.rotor_friction * omega_r_) / p_.gear_ratio -
                p_.generator_friction * omega_g_;
  for (std::size_t i = 0; i < delay_samples_; ++i) wind_delay_.emplace_back(v, wind_.shear_exponent);
  index_ = -static_cast<int64_t>(std::llround(kSettleTime / dt_));
  t_ = static_cast<double>(index_) * dt_;
  settle(kSettleTime);
}

void TurbineSim::settle(double seconds) {
  const int n = static_cast<int>(std::lround(seconds / dt_));
  for (int i = 0; i < n; ++i) advance(ControlInput{}, false);
  index_ = 0;
  t_ = 0.0;
  k_ = 0;
}

bool TurbineSim::fault_active(const FaultSpec& f) const {
  if (f.target.rfind("pitch_actuator_", 0) == 0) return pitch_alpha(f) > 0.0;
  if (f.type == "ice_accretion") return t_ >= f.start && t_ < f.end;
  if (f.type == "ice_shedding") return t_ >= f.start && t_ < std::min(f.end, f.start + 60.0);
  return t_ >= f.start && t_ < f.end;
}

double TurbineSim::pitch_alpha(const FaultSpec& f) const {
  // Abrupt (no ramps) or gradual: ramp in, hold until `end`, ramp out (Wu & Li eqs 11-13's indicator).
  if (t_ < f.start) return 0.0;
  if (t_ < f.start + f.ramp_in) return f.alpha * (t_ - f.start) / f.ramp_in;
  if (t_ < f.end) return f.alpha;
  if (f.ramp_out > 0.0 && t_ < f.end + f.ramp_out) return f.alpha * (1.0 - (t_ - f.end) / f.ramp_out);
  return 0.0;
}

std::vector<bool> TurbineSim::faults_active() const {
  std::vector<bool> out;
  for (const auto& f : faults_) out.push_back(fault_active(f));
  return out;
}

double TurbineSim::measure(const std::string& channel, double true_value, double noise_std, bool inject) {
  double v = true_value + noise_std * normal_(rng_);
  if (!inject) return v;
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const FaultSpec& f = faults_[i];
    const bool targets = f.target == channel || (f.target == "lidar" && channel.rfind("lidar_v_", 0) == 0);
    if (!targets) continue;
    if (!fault_active(f)) {
      stuck_latched_[i] = false;
      continue;
    }
    const double since = t_ - f.start;
    if (f.type == "bias" || f.type == "offset") {
      v += f.value;
    } else if (f.type == "bias_paper") {
      // Witczak et al. eqs 41-42: a state-dependent bias, k counted from the fault's start.
      const double k = std::floor(since / dt_ + 1e-6);
      v += f.amplitude * (true_value * std::sin(k / 500.0) + true_value * std::sin(k / 1000.0) + true_value);
    } else if (f.type == "gain") {
      v *= f.gain;
    } else if (f.type == "drift") {
      v += f.rate * since;
    } else if (f.type == "stuck") {
      if (!stuck_latched_[i]) {
        stuck_value_[i] = f.has_value ? f.value : v;
        stuck_latched_[i] = true;
      }
      v = stuck_value_[i];
    } else if (f.type == "intermittent") {
      if (std::fmod(since, f.period) < f.duty * f.period) v = f.gain * v + f.value;
    } else if (f.type == "invalid") {
      v = kNaN;
    }
  }
  return v;
}

void TurbineSim::update_wind() {
  // Turbulence: Ornstein-Uhlenbeck (first-order low-pass white noise), std = TI * mean,
  // time constant = length_scale / mean; the shear exponent varies slowly the same way.
  const double tau = wind_.length_scale / wind_.mean;
  const double a = std::exp(-dt_ / tau);
  const double sigma = wind_.turbulence_intensity * wind_.mean;
  turbulence_ = a * turbulence_ + sigma * std::sqrt(1.0 - a * a) * normal_(rng_);
  const double as = std::exp(-dt_ / wind_.shear_time_constant);
  shear_dev_ = as * shear_dev_ + wind_.shear_variation * std::sqrt(1.0 - as * as) * normal_(rng_);
  const double upstream = std::max(0.5, wind_.mean + turbulence_);
  const double shear = wind_.shear_exponent + shear_dev_;
  wind_delay_.emplace_back(upstream, shear);
  while (wind_delay_.size() > delay_samples_ + 1) wind_delay_.pop_front();
  truth_.wind_upstream = upstream;

  lidar_updated_ = false;
  lidar_timer_ += dt_;
  if (lidar_timer_ >= 1.0 / wind_.lidar_rate - 1e-9) {
    lidar_timer_ = 0.0;
    lidar_updated_ = true;
    const double h = p_.hub_height, r2 = 0.5 * p_.rotor_radius;
    lidar_upper_ = upstream * std::pow((h + r2) / h, shear) + wind_.lidar_noise * normal_(rng_);
    lidar_lower_ = upstream * std::pow((h - r2) / h, shear) + wind_.lidar_noise * normal_(rng_);
  }
}

void TurbineSim::controller(const ControlInput& in, const FrameSample& m, std::array<double, 3>& pitch_ref,
                            double& torque_ref) {
  const double omega_rated_g = p_.rated_generator_speed;
  double wg = (in.use_corrected_generator_speed && std::isfinite(in.corrected_generator_speed))
                  ? in.corrected_generator_speed
                  : m.generator_speed;
  if (!std::isfinite(wg)) wg = speed_filtered_;  // an invalid sample: hold the last filtered value
  speed_filtered_ += (wg - speed_filtered_) * dt_ / (ctl_.speed_filter + dt_);

  if (in.mode == OperatingMode::kSafeStop) {
    // Feather at the rate limit and ramp the torque down.
    if (stop_torque_ < 0) stop_torque_ = gen_torque_;
    stop_torque_ = std::max(0.0, stop_torque_ - gen_torque_ / ctl_.stop_torque_time * dt_ - 1.0);
    torque_ref = stop_torque_;
    pitch_ref = {p_.pitch_max, p_.pitch_max, p_.pitch_max};
    pitch_integral_ = p_.pitch_max;
    return;
  }
  stop_torque_ = -1;
  const bool degraded = in.mode == OperatingMode::kDegraded;
  const double speed_share = degraded ? ctl_.degraded_speed : 1.0;
  const double omega_ref = omega_rated_g * speed_share;
  const double power_share = degraded ? ctl_.degraded_power : 1.0;
  const double torque_max = p_.rated_power * power_share / (p_.generator_efficiency * omega_ref);
  // Region 2: K omega^2 from Cp's maximum, referred to the generator side.
  static const double lambda_opt = AeroModel::optimal_tip_speed_ratio();
  static const double cp_max = AeroModel::power_coefficient(lambda_opt, 0.0);
  const double k_opt = 0.5 * p_.air_density * p_.rotor_area() * std::pow(p_.rotor_radius, 3) * cp_max /
                       std::pow(lambda_opt, 3) / std::pow(p_.gear_ratio, 3);
  torque_ref = std::min(k_opt * speed_filtered_ * speed_filtered_, torque_max);

  // Region 3: gain-scheduled PI on generator speed; gains scale with the (iced) inertia when adapted.
  const double inertia_scale = in.inertia > 0.0 ? in.inertia / p_.lumped_inertia() : 1.0;
  const double beta_c = std::max(0.0, pitch_integral_);
  const double gs = inertia_scale / (1.0 + beta_c / ctl_.gain_schedule_pitch);
  const double e = speed_filtered_ - omega_ref;
  pitch_integral_ = std::clamp(pitch_integral_ + ctl_.pitch_ki * gs * e * dt_, 0.0, p_.pitch_max);
  const double collective = std::clamp(pitch_integral_ + ctl_.pitch_kp * gs * e, 0.0, p_.pitch_max);

  // IPC on the 1P load (Coleman d-q), from the strain gauges or the LIDAR load model.
  const bool ipc_on = in.ipc_source != IpcSource::kOff && collective > 1.0;
  std::array<double, 3> moment{};
  bool moments_ok = true;
  const double psi1 = m.azimuth;
  if (in.ipc_source == IpcSource::kStrainGauge) {
    moment = m.blade_moment;
  } else if (in.ipc_source == IpcSource::kLidarModel) {
    // The LIDAR measurement of D / V ago is the wind at the rotor now.
    double vu = kNaN, vl = kNaN;
    const double v_est = std::isfinite(lidar_upper_) ? 0.5 * (lidar_upper_ + lidar_lower_) : wind_.mean;
    const double want = t_ - wind_.lidar_distance / std::max(v_est, 1.0);
    for (auto it = lidar_history_.rbegin(); it != lidar_history_.rend(); ++it)
      if ((*it)[0] <= want) {
        vu = (*it)[1];
        vl = (*it)[2];
        break;
      }
    const double h = p_.hub_height, r2 = 0.5 * p_.rotor_radius;
    moments_ok = std::isfinite(vu) && std::isfinite(vl) && vu > 0 && vl > 0;
    if (moments_ok) {
      const double alpha = std::log(vu / vl) / std::log((h + r2) / (h - r2));
      const double v_hub = vu / std::pow((h + r2) / h, alpha);
      const double lambda = aero_.tip_speed_ratio(v_hub, m.rotor_speed);
      for (int i = 0; i < 3; ++i) {
        const double psi = psi1 + i * 2.0 * M_PI / 3.0;
        const double vi = v_hub * std::pow((h + p_.load_radius * p_.rotor_radius * std::cos(psi)) / h, alpha);
        moment[i] = aero_.moment_coefficient(lambda, pitch_ref_[i]) * vi * vi;
      }
    }
  }
  for (double x : moment) moments_ok = moments_ok && std::isfinite(x);
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
    pitch_ref[i] =
        std::clamp(collective + ipc_d_ * std::cos(psi) + ipc_q_ * std::sin(psi), p_.pitch_min, p_.pitch_max);
  }
}

void TurbineSim::advance(const ControlInput& input, bool inject) {
  update_wind();
  const double v_rotor = wind_delay_.front().first;
  const double shear = wind_delay_.front().second;

  // Ice: accretion ramps up to its mass; shedding drops a share of what is there at that moment.
  double ice = ice_initial_ - ice_shed_;
  for (const auto& f : faults_)
    if (inject && f.type == "ice_accretion" && t_ >= f.start)
      ice += f.value * (f.ramp_in > 0 ? std::min(1.0, (t_ - f.start) / f.ramp_in) : 1.0);
  for (std::size_t i = 0; i < faults_.size(); ++i)
    if (inject && faults_[i].type == "ice_shedding" && t_ >= faults_[i].start && !shed_done_[i]) {
      ice_shed_ += faults_[i].fraction * std::max(0.0, ice);
      ice -= faults_[i].fraction * std::max(0.0, ice);
      shed_done_[i] = true;
    }
  ice_mass_ = std::max(0.0, ice);
  const double rotor_inertia = p_.rotor_inertia + ice_mass_ * p_.ice_radius * p_.ice_radius;
  const double cp_scale = std::max(0.0, 1.0 - p_.ice_cp_loss * ice_mass_ / 1000.0);

  double eta = p_.drive_train_efficiency, torque_offset = 0.0;
  std::array<double, 3> wn{}, zeta{};
  for (int b = 0; b < 3; ++b) {
    wn[b] = p_.pitch_omega_n;
    zeta[b] = p_.pitch_zeta;
  }
  if (inject)
    for (const auto& f : faults_) {
      if (f.type == "efficiency" && fault_active(f)) eta = f.value;
      if (f.type == "torque_offset" && fault_active(f)) torque_offset = f.value;
      if (f.target.rfind("pitch_actuator_", 0) == 0) {
        const double alpha = pitch_alpha(f);
        if (alpha <= 0.0) continue;
        const int b = f.target.back() - '1';
        for (const auto& sig : kPitchFaults)
          if (f.type == sig.type) {
            // Wu & Li eqs 11-13.
            wn[b] = (1 - alpha) * p_.pitch_omega_n + alpha * sig.omega_n;
            zeta[b] = (1 - alpha) * p_.pitch_zeta + alpha * sig.zeta;
          }
      }
    }

  // Aerodynamics and blade loads at the current state.
  const double lambda = aero_.tip_speed_ratio(v_rotor, omega_r_);
  double t_aero = 0.0;
  for (int i = 0; i < 3; ++i)
    t_aero += aero_.aero_torque(v_rotor, omega_r_, actuator_[i].angle, cp_scale) / 3.0;
  const double h = p_.hub_height;
  std::array<double, 3> moment{};
  for (int i = 0; i < 3; ++i) {
    const double psi = azimuth_ + i * 2.0 * M_PI / 3.0;
    const double height = h + p_.load_radius * p_.rotor_radius * std::cos(psi);
    const double shadow =
        1.0 - wind_.tower_shadow * std::exp(-std::pow(wrap_pi(psi - M_PI) / kShadowWidth, 2));
    const double vi = v_rotor * std::pow(height / h, shear) * shadow;
    moment[i] = aero_.moment_coefficient(lambda, actuator_[i].angle) * vi * vi;
  }

  // Truth, including the first harmonic over the last revolution: a = (1/pi) \int M cos(psi) dpsi.
  const double dpsi = std::max(0.0, omega_r_ * dt_);
  std::array<double, 7> rev{dpsi};
  for (int i = 0; i < 3; ++i) {
    const double psi = azimuth_ + i * 2.0 * M_PI / 3.0;
    rev[1 + 2 * i] = moment[i] * std::cos(psi) * dpsi;
    rev[2 + 2 * i] = moment[i] * std::sin(psi) * dpsi;
  }
  revolution_.push_back(rev);
  for (int j = 0; j < 7; ++j) revolution_sum_[j] += rev[j];
  while (revolution_.size() > 1 && revolution_sum_[0] - revolution_.front()[0] >= 2.0 * M_PI) {
    for (int j = 0; j < 7; ++j) revolution_sum_[j] -= revolution_.front()[j];
    revolution_.pop_front();
  }
  truth_.rotor_speed = omega_r_;
  truth_.generator_speed = omega_g_;
  truth_.torsion = theta_;
  for (int i = 0; i < 3; ++i) truth_.pitch[i] = actuator_[i].angle;
  truth_.blade_moment = moment;
  // The window must span exactly 2 pi, or the mean load leaks into the first harmonic: weight the oldest
  // step by the share of it that lies inside.
  const double excess = revolution_sum_[0] - 2.0 * M_PI;
  const auto& oldest = revolution_.front();
  const double keep = oldest[0] > 0.0 ? std::clamp(1.0 - excess / oldest[0], 0.0, 1.0) : 1.0;
  for (int i = 0; i < 3; ++i) {
    const double a = revolution_sum_[1 + 2 * i] - (1.0 - keep) * oldest[1 + 2 * i];
    const double b = revolution_sum_[2 + 2 * i] - (1.0 - keep) * oldest[2 + 2 * i];
    truth_.a1[i] = excess >= -1e-9 ? std::hypot(a, b) / M_PI : kNaN;
  }
  truth_.inertia = p_.lumped_inertia(ice_mass_ * p_.ice_radius * p_.ice_radius);
  truth_.ice_mass = ice_mass_;
  truth_.aero_torque = t_aero;
  truth_.aero_power = t_aero * omega_r_;
  truth_.gen_torque = gen_torque_ + torque_offset;
  truth_.wind_hub = v_rotor;
  truth_.shear_exponent = shear;

  // Sensors.
  FrameSample& s = sample_;
  s.sequence = k_;
  s.t = t_;
  s.valid_mask = kValidAll;
  s.rotor_speed = measure("rotor_speed", omega_r_, noise_.rotor_speed, inject);
  s.generator_speed = measure("generator_speed", omega_g_, noise_.generator_speed, inject);
  s.gen_torque = measure("gen_torque", gen_torque_ + torque_offset, noise_.gen_torque, inject);
  s.power = measure("power", p_.generator_efficiency * omega_g_ * (gen_torque_ + torque_offset), noise_.power,
                    inject);
  s.wind_hub = measure("wind_hub", v_rotor, noise_.wind_hub, inject);
  s.azimuth = std::fmod(azimuth_, 2.0 * M_PI);
  static const char* kPitch[] = {"pitch_1", "pitch_2", "pitch_3"};
  static const char* kMoment[] = {"blade_moment_1", "blade_moment_2", "blade_moment_3"};
  for (int i = 0; i < 3; ++i) {
    s.pitch[i] = measure(kPitch[i], actuator_[i].angle, noise_.pitch, inject);
    s.blade_moment[i] = measure(kMoment[i], moment[i], noise_.blade_moment, inject);
  }
  s.lidar_v_upper = measure("lidar_v_upper", lidar_upper_, 0.0, inject);
  s.lidar_v_lower = measure("lidar_v_lower", lidar_lower_, 0.0, inject);
  s.aero_torque = t_aero;
  s.aero_power = t_aero * omega_r_;
  const double* channels[] = {&s.rotor_speed, &s.generator_speed, &s.gen_torque, &s.power, &s.wind_hub};
  const uint32_t bits[] = {kValidRotorSpeed, kValidGeneratorSpeed, kValidGenTorque, kValidPower,
                           kValidWindHub};
  for (int c = 0; c < 5; ++c)
    if (!std::isfinite(*channels[c])) s.valid_mask &= ~bits[c];
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(s.pitch[i])) s.valid_mask &= ~(kValidPitch1 << i);
    if (!std::isfinite(s.blade_moment[i])) s.valid_mask &= ~(kValidBladeMoment1 << i);
  }
  if (!std::isfinite(s.lidar_v_upper) || !std::isfinite(s.lidar_v_lower)) s.valid_mask &= ~kValidLidar;
  if (lidar_updated_) {
    lidar_history_.push_back({t_, s.lidar_v_upper, s.lidar_v_lower});
    while (lidar_history_.size() > 200) lidar_history_.pop_front();
  }

  // Controller: the references are held over the next sample (zero-order hold).
  double torque_ref = 0.0;
  std::array<double, 3> pitch_ref{};
  controller(input, s, pitch_ref, torque_ref);
  pitch_ref_ = pitch_ref;
  s.pitch_ref = pitch_ref;
  s.gen_torque_ref = torque_ref;

  // Dynamics over one sample.
  const double h_sub = dt_ / kSubsteps;
  const double conv = 1.0 - std::exp(-h_sub / p_.converter_time_constant);
  const double n = p_.gear_ratio, jr = rotor_inertia, jg = p_.generator_inertia;
  const double kdt = p_.drive_train_stiffness, bdt = p_.drive_train_damping, br = p_.rotor_friction,
               bg = p_.generator_friction;
  for (int sub = 0; sub < kSubsteps; ++sub) {
    gen_torque_ += (torque_ref - gen_torque_) * conv;
    const double tg = gen_torque_ + torque_offset;
    // Witczak et al. eqs 31-33.
    auto f = [&](const std::array<double, 3>& x) {
      return std::array<double, 3>{
          -(bdt + br) / jr * x[0] + bdt / (n * jr) * x[1] - kdt / jr * x[2] + t_aero / jr,
          eta * bdt / (n * jg) * x[0] - (eta * bdt / (n * n * jg) + bg / jg) * x[1] +
              eta * kdt / (n * jg) * x[2] - tg / jg,
          x[0] - x[1] / n};
    };
    std::array<double, 3> x{omega_r_, omega_g_, theta_};
    const auto k1 = f(x);
    std::array<double, 3> x2, x3, x4;
    for (int j = 0; j < 3; ++j) x2[j] = x[j] + 0.5 * h_sub * k1[j];
    const auto k2 = f(x2);
    for (int j = 0; j < 3; ++j) x3[j] = x[j] + 0.5 * h_sub * k2[j];
    const auto k3 = f(x3);
    for (int j = 0; j < 3; ++j) x4[j] = x[j] + h_sub * k3[j];
    const auto k4 = f(x4);
    for (int j = 0; j < 3; ++j) x[j] += h_sub / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    omega_r_ = std::max(0.0, x[0]);
    omega_g_ = std::max(0.0, x[1]);
    theta_ = x[2];

    for (int b = 0; b < 3; ++b)
      actuator_[b].step(pitch_ref[b], h_sub, wn[b], zeta[b],
                        std::min(p_.pitch_rate_limit, input.pitch_rate_limit[b]), p_.pitch_min, p_.pitch_max);
    azimuth_ += omega_r_ * h_sub;
  }
  azimuth_ = std::fmod(azimuth_, 2.0 * M_PI);
  // Time from the sample index, not a running sum: a fault due at 10 s starts at the sample stamped 10 s.
  ++index_;
  t_ = static_cast<double>(index_) * dt_;
  if (index_ > 0) k_ = static_cast<uint64_t>(index_);
}

void PitchActuator::step(double ref, double h, double wn, double zeta, double limit, double lo, double hi) {
  const double w2 = wn * wn, c = 2.0 * zeta * wn;
  auto acc = [&](double be, double ra) { return -c * ra - w2 * (be - ref); };
  const double b0 = angle, r0 = rate;
  const double k1b = r0, k1r = acc(b0, r0);
  const double k2b = r0 + 0.5 * h * k1r, k2r = acc(b0 + 0.5 * h * k1b, k2b);
  const double k3b = r0 + 0.5 * h * k2r, k3r = acc(b0 + 0.5 * h * k2b, k3b);
  const double k4b = r0 + h * k3r, k4r = acc(b0 + h * k3b, k4b);
  double b_new = b0 + h / 6.0 * (k1b + 2 * k2b + 2 * k3b + k4b);
  double r_new = r0 + h / 6.0 * (k1r + 2 * k2r + 2 * k3r + k4r);
  if (std::fabs(r_new) > limit) {
    // The valve saturates: the angle moves at the rate limit.
    r_new = std::clamp(r_new, -limit, limit);
    b_new = b0 + 0.5 * h * (r0 + r_new);
  }
  if (b_new < lo || b_new > hi) {
    b_new = std::clamp(b_new, lo, hi);
    r_new = 0.0;
  }
  angle = b_new;
  rate = r_new;
}

const FrameSample& TurbineSim::step(const ControlInput& input) {
  advance(input, true);
  return sample_;
}

std::vector<std::string> TurbineSim::truth_columns() const {
  std::vector<std::string> c = {"true_rotor_speed",    "true_generator_speed",
                                "true_pitch_1",        "true_pitch_2",
                                "true_pitch_3",        "true_blade_moment_1",
                                "true_blade_moment_2", "true_blade_moment_3",
                                "true_a1_1",           "true_a1_2",
                                "true_a1_3",           "true_inertia",
                                "true_ice_mass",       "true_wind_hub",
                                "true_gen_torque"};
  for (const auto& f : faults_) c.push_back("fault_active_" + f.target + "_" + f.type);
  return c;
}

std::vector<double> TurbineSim::truth_values() const {
  const Truth& t = truth_;
  std::vector<double> v = {t.rotor_speed,     t.generator_speed, t.pitch[0],        t.pitch[1], t.pitch[2],
                           t.blade_moment[0], t.blade_moment[1], t.blade_moment[2], t.a1[0],    t.a1[1],
                           t.a1[2],           t.inertia,         t.ice_mass,        t.wind_hub, t.gen_torque};
  for (bool a : faults_active()) v.push_back(a ? 1.0 : 0.0);
  return v;
}

}  // namespace windfdi::plant
