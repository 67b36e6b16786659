// One simulated benchmark turbine: aerodynamics, blade loads, icing and plant faults (pitch actuator: Wu & Li
// eqs 11-13 with Table 1), around its wind, sensors, controller and dynamics.
#include "turbine_sim.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "fault_schedule.hpp"
#include "lidar_shear.hpp"

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
constexpr TableSignature kTableHealthy = {"none", 11.11, 0.6};
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
      faults_(faults),
      noise_(noise),
      dt_(1.0 / sample_rate),
      random_(mix_seed(seed, turbine.id)),
      wind_(turbine.wind, params, dt_),
      sensors_(faults, dt_),
      controller_(params, controller, turbine.wind.lidar_distance, turbine.wind.mean, dt_),
      ice_mass_(turbine.ice_mass),
      ice_initial_(turbine.ice_mass),
      shed_done_(faults.size(), false) {
  const double v = turbine.wind.mean;
  // Start at the operating point of the mean wind.
  const double lambda_opt = AeroModel::optimal_tip_speed_ratio();
  const double omega_rated = p_.rated_generator_speed / p_.gear_ratio;
  DriveTrain& x = drive_train_;
  x.rotor_speed = std::min(lambda_opt * v / p_.rotor_radius, omega_rated);
  double beta = 0.0;
  if (x.rotor_speed >= omega_rated - 1e-9) {
    double lo = 0.0, hi = 45.0;
    const double target = p_.rated_power / p_.generator_efficiency / p_.drive_train_efficiency;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (aero_.aero_power(v, x.rotor_speed, mid) > target ? lo : hi) = mid;
    }
    beta = 0.5 * (lo + hi);
  }
  x.generator_speed = x.rotor_speed * p_.gear_ratio;
  for (auto& a : actuator_) a.angle = beta;
  controller_.start_at(beta, x.generator_speed);
  const double t_aero = aero_.aero_torque(v, x.rotor_speed, beta);
  x.torsion = (t_aero - p_.rotor_friction * x.rotor_speed) / p_.drive_train_stiffness;
  gen_torque_ = p_.drive_train_efficiency * (t_aero - p_.rotor_friction * x.rotor_speed) / p_.gear_ratio -
                p_.generator_friction * x.generator_speed;
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

std::vector<bool> TurbineSim::faults_active() const {
  std::vector<bool> out;
  for (const auto& f : faults_) out.push_back(fault_active(f, t_));
  return out;
}

void TurbineSim::advance(const ControlInput& input, bool inject) {
  wind_.step(random_);
  truth_.wind_upstream = wind_.upstream();
  const ShearProfile rotor = wind_.at_rotor();
  const double v_rotor = rotor.hub_speed;
  double& omega_r = drive_train_.rotor_speed;
  const double& omega_g = drive_train_.generator_speed;

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
      if (f.type == "efficiency" && fault_active(f, t_)) eta = f.value;
      if (f.type == "torque_offset" && fault_active(f, t_)) torque_offset = f.value;
      if (f.target.rfind("pitch_actuator_", 0) == 0) {
        const double alpha = pitch_fault_indicator(f, t_);
        if (alpha <= 0.0) continue;
        const int b = f.target.back() - '1';
        for (const auto& sig : kPitchFaults)
          if (f.type == sig.type) {
            // Wu & Li eqs 11-13.
            // Table 1's faults are relative changes of its healthy actuator (11.11 rad/s, 0.6): another
            // turbine's actuator takes them as shares of its own.
            wn[b] = (1 - alpha) * p_.pitch_omega_n +
                    alpha * sig.omega_n * p_.pitch_omega_n / kTableHealthy.omega_n;
            zeta[b] = (1 - alpha) * p_.pitch_zeta + alpha * sig.zeta * p_.pitch_zeta / kTableHealthy.zeta;
          }
      }
    }

  // Aerodynamics and blade loads at the current state.
  const double lambda = aero_.tip_speed_ratio(v_rotor, omega_r);
  double t_aero = 0.0;
  for (int i = 0; i < 3; ++i)
    t_aero += aero_.aero_torque(v_rotor, omega_r, actuator_[i].angle, cp_scale) / 3.0;
  const double h = p_.hub_height;
  std::array<double, 3> moment{};
  for (int i = 0; i < 3; ++i) {
    const double psi = azimuth_ + i * 2.0 * M_PI / 3.0;
    const double height = h + p_.load_radius * p_.rotor_radius * std::cos(psi);
    const double shadow =
        1.0 - wind_.config().tower_shadow * std::exp(-std::pow(wrap_pi(psi - M_PI) / kShadowWidth, 2));
    const double vi = rotor.at(height) * shadow;
    moment[i] = aero_.moment_coefficient(lambda, actuator_[i].angle) * vi * vi;
  }

  // Truth, including the first harmonic over the last revolution: a = (1/pi) \int M cos(psi) dpsi.
  const double dpsi = std::max(0.0, omega_r * dt_);
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
  truth_.rotor_speed = omega_r;
  truth_.generator_speed = omega_g;
  truth_.torsion = drive_train_.torsion;
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
  truth_.aero_power = t_aero * omega_r;
  truth_.gen_torque = gen_torque_ + torque_offset;
  truth_.wind_hub = v_rotor;
  truth_.shear_exponent = rotor.exponent;

  // Sensors.
  FrameSample& s = sample_;
  s.sequence = k_;
  s.t = t_;
  s.valid_mask = kValidAll;
  const auto measure = [&](const char* channel, double true_value, double noise_std) {
    return sensors_.measure(channel, true_value, noise_std, t_, inject, random_);
  };
  s.rotor_speed = measure("rotor_speed", omega_r, noise_.rotor_speed);
  s.generator_speed = measure("generator_speed", omega_g, noise_.generator_speed);
  s.gen_torque = measure("gen_torque", gen_torque_ + torque_offset, noise_.gen_torque);
  s.power = measure("power", p_.generator_efficiency * omega_g * (gen_torque_ + torque_offset), noise_.power);
  s.wind_hub = measure("wind_hub", v_rotor, noise_.wind_hub);
  s.azimuth = std::fmod(azimuth_, 2.0 * M_PI);
  static const char* kPitch[] = {"pitch_1", "pitch_2", "pitch_3"};
  static const char* kMoment[] = {"blade_moment_1", "blade_moment_2", "blade_moment_3"};
  for (int i = 0; i < 3; ++i) {
    s.pitch[i] = measure(kPitch[i], actuator_[i].angle, noise_.pitch);
    s.blade_moment[i] = measure(kMoment[i], moment[i], noise_.blade_moment);
  }
  s.lidar_v_upper = measure("lidar_v_upper", wind_.lidar_upper(), 0.0);
  s.lidar_v_lower = measure("lidar_v_lower", wind_.lidar_lower(), 0.0);
  s.aero_torque = t_aero;
  s.aero_power = t_aero * omega_r;
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

  // Controller: the references are held over the next sample (zero-order hold).
  const ControllerOutput ref = controller_.step(t_, input, s, wind_.lidar_updated(), gen_torque_);
  s.pitch_ref = ref.pitch_ref;
  s.gen_torque_ref = ref.torque_ref;

  // Dynamics over one sample.
  const double h_sub = dt_ / kSubsteps;
  const double conv = 1.0 - std::exp(-h_sub / p_.converter_time_constant);
  for (int sub = 0; sub < kSubsteps; ++sub) {
    gen_torque_ += (ref.torque_ref - gen_torque_) * conv;
    drive_train_.step(p_, rotor_inertia, eta, t_aero, gen_torque_ + torque_offset, h_sub);
    for (int b = 0; b < 3; ++b)
      actuator_[b].step(ref.pitch_ref[b], h_sub, wn[b], zeta[b], p_.pitch_rate_limit, p_.pitch_min,
                        p_.pitch_max);
    azimuth_ += omega_r * h_sub;
  }
  azimuth_ = std::fmod(azimuth_, 2.0 * M_PI);
  // Time from the sample index, not a running sum: a fault due at 10 s starts at the sample stamped 10 s.
  ++index_;
  t_ = static_cast<double>(index_) * dt_;
  if (index_ > 0) k_ = static_cast<uint64_t>(index_);
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
