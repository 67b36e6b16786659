// LIDAR load model (Stotsky 2014 eqs 1, 9) and its look-up table with bounded adaptation.
#include "load_model.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "lidar_shear.hpp"
#include "yaml_config.hpp"

namespace windfdi::blade_load {

LoadTable::LoadTable(double lambda0, double lambda_step, int n_lambda, double pitch0, double pitch_step,
                     int n_pitch, std::vector<double> k)
    : l0_(lambda0),
      dl_(lambda_step),
      p0_(pitch0),
      dp_(pitch_step),
      nl_(n_lambda),
      np_(n_pitch),
      k_(std::move(k)),
      f_(k_.size(), 1.0) {}

namespace {
std::vector<double> split_numbers(const std::string& line, const std::string& file, int lineno, int skip) {
  std::vector<double> out;
  std::stringstream ss(line);
  std::string field;
  int col = 0;
  while (std::getline(ss, field, ',')) {
    ++col;
    if (col <= skip) continue;
    try {
      std::size_t used = 0;
      const double v = std::stod(field, &used);
      if (!std::isfinite(v)) throw std::invalid_argument("");
      out.push_back(v);
    } catch (const std::exception&) {
      throw ConfigError(file, lineno, "column " + std::to_string(col),
                        "'" + field + "' is not a finite number");
    }
  }
  return out;
}
}  // namespace

LoadTable LoadTable::from_turbine(const TurbineParams& turbine) {
  const AeroModel aero(turbine);
  const double l0 = 0.0, dl = 0.25, p0 = -5.0, dp = 0.5;
  const int nl = 81, np = 101;
  std::vector<double> k;
  k.reserve(static_cast<std::size_t>(nl * np));
  for (int i = 0; i < nl; ++i)
    for (int j = 0; j < np; ++j) k.push_back(aero.moment_coefficient_exact(l0 + i * dl, p0 + j * dp));
  return LoadTable(l0, dl, nl, p0, dp, np, std::move(k));
}

LoadTable LoadTable::load_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, 0, "", "cannot open load table");
  std::string line;
  int lineno = 0;
  std::vector<double> pitch, lambda, k;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (pitch.empty()) {
      if (line.rfind("lambda", 0) != 0)
        throw ConfigError(path, lineno, "", "expected the header 'lambda\\pitch_deg,...'");
      pitch = split_numbers(line, path, lineno, 1);
      if (pitch.size() < 2) throw ConfigError(path, lineno, "", "need at least two pitch values");
      continue;
    }
    const auto row = split_numbers(line, path, lineno, 0);
    if (row.size() != pitch.size() + 1)
      throw ConfigError(
          path, lineno, "",
          "expected " + std::to_string(pitch.size() + 1) + " fields, got " + std::to_string(row.size()));
    lambda.push_back(row[0]);
    k.insert(k.end(), row.begin() + 1, row.end());
  }
  if (lambda.size() < 2) throw ConfigError(path, lineno, "", "need at least two tip-speed-ratio rows");
  auto regular = [&](const std::vector<double>& v, const char* what) {
    const double step = v[1] - v[0];
    if (!(step > 0)) throw ConfigError(path, 0, what, "grid must increase");
    for (std::size_t i = 1; i < v.size(); ++i)
      if (std::fabs(v[i] - v[0] - static_cast<double>(i) * step) > 1e-6 * (1 + std::fabs(v[i])))
        throw ConfigError(path, 0, what, "grid must be regular");
    return step;
  };
  const double dl = regular(lambda, "lambda"), dp = regular(pitch, "pitch");
  return LoadTable(lambda[0], dl, static_cast<int>(lambda.size()), pitch[0], dp,
                   static_cast<int>(pitch.size()), std::move(k));
}

void LoadTable::save_csv(const std::string& path, const std::string& comment) const {
  std::ofstream out(path);
  if (!out) throw ConfigError(path, 0, "", "cannot write load table");
  std::stringstream c(comment);
  std::string l;
  while (std::getline(c, l)) out << "# " << l << "\n";
  out.precision(10);
  out << "lambda\\pitch_deg";
  for (int j = 0; j < np_; ++j) out << "," << p0_ + j * dp_;
  out << "\n";
  for (int i = 0; i < nl_; ++i) {
    out << l0_ + i * dl_;
    for (int j = 0; j < np_; ++j)
      out << "," << k_[static_cast<std::size_t>(i * np_ + j)] * f_[static_cast<std::size_t>(i * np_ + j)];
    out << "\n";
  }
}

double LoadTable::bilinear(const std::vector<double>& v, double lambda, double pitch_deg) const {
  const double x = std::clamp((lambda - l0_) / dl_, 0.0, nl_ - 1.0);
  const double y = std::clamp((pitch_deg - p0_) / dp_, 0.0, np_ - 1.0);
  const int i = std::min(static_cast<int>(x), nl_ - 2), j = std::min(static_cast<int>(y), np_ - 2);
  const double fx = x - i, fy = y - j;
  auto at = [&](int a, int b) { return v[static_cast<std::size_t>(a * np_ + b)]; };
  return (1 - fx) * ((1 - fy) * at(i, j) + fy * at(i, j + 1)) +
         fx * ((1 - fy) * at(i + 1, j) + fy * at(i + 1, j + 1));
}

double LoadTable::k(double lambda, double pitch_deg) const {
  // The corrected surface, node by node (k_M times its factor), so interpolation stays bilinear in it.
  const double x = std::clamp((lambda - l0_) / dl_, 0.0, nl_ - 1.0);
  const double y = std::clamp((pitch_deg - p0_) / dp_, 0.0, np_ - 1.0);
  const int i = std::min(static_cast<int>(x), nl_ - 2), j = std::min(static_cast<int>(y), np_ - 2);
  const double fx = x - i, fy = y - j;
  auto at = [&](int a, int b) {
    const auto n = static_cast<std::size_t>(a * np_ + b);
    return k_[n] * f_[n];
  };
  return (1 - fx) * ((1 - fy) * at(i, j) + fy * at(i, j + 1)) +
         fx * ((1 - fy) * at(i + 1, j) + fy * at(i + 1, j + 1));
}

double LoadTable::factor(double lambda, double pitch_deg) const { return bilinear(f_, lambda, pitch_deg); }

void LoadTable::adapt(double lambda, double pitch_deg, double target, double gain, double sl, double sp,
                      double bound) {
  // The surface moves only near the operating point where data were gathered (Stotsky 2014: "the part of the
  // surface parameters is adapted"), each node by at most `gain` of the way per update and within bounds.
  const int i0 = std::max(0, static_cast<int>(std::floor((lambda - 3 * sl - l0_) / dl_)));
  const int i1 = std::min(nl_ - 1, static_cast<int>(std::ceil((lambda + 3 * sl - l0_) / dl_)));
  const int j0 = std::max(0, static_cast<int>(std::floor((pitch_deg - 3 * sp - p0_) / dp_)));
  const int j1 = std::min(np_ - 1, static_cast<int>(std::ceil((pitch_deg - p0_ + 3 * sp) / dp_)));
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const double a = (l0_ + i * dl_ - lambda) / sl, b = (p0_ + j * dp_ - pitch_deg) / sp;
      const double w = std::exp(-0.5 * (a * a + b * b));
      double& f = f_[static_cast<std::size_t>(i * np_ + j)];
      f = std::clamp(f + gain * w * (target - f), 1.0 - bound, 1.0 + bound);
    }
}

LidarLoadModel::LidarLoadModel(const LoadModelConfig& c, const LoadTable* table) : c_(c), table_(table) {}

void LidarLoadModel::reset() {
  history_.clear();
  have_adv_ = false;
}

bool LidarLoadModel::add_lidar(double t, double vu, double vl) {
  if (!std::isfinite(vu) || !std::isfinite(vl) || vu < 0.5 || vl < 0.5 || vu > 60.0 || vl > 60.0)
    return false;
  // Sample time that went back (a restarted plant) or jumped (a stepped clock): the delayed speeds looked up
  // from now on are not in this history (a restarted plant raised "no delayed LIDAR speeds" on every
  // turbine).
  const bool restart =
      !history_.empty() && (t < history_.back()[0] || t > history_.back()[0] + kLidarHistoryMaxStep);
  if (restart) reset();
  if (!history_.empty() && history_.back()[1] == vu && history_.back()[2] == vl) return false;  // held value
  history_.push_back({t, vu, vl});
  // Advection speed V: the slowly filtered hub speed (frozen turbulence moves with the mean flow).
  const double v = 0.5 * (vu + vl);
  if (!have_adv_) {
    v_adv_ = v;
    t_adv0_ = t;
    have_adv_ = true;
  } else {
    // Until advection_time has passed, the running mean of everything seen (not the first sample, which is
    // off by the turbulence, TI * V, and would bias D / V by as much for several advection times); then the
    // first-order low-pass.
    const double dt = std::max(0.0, t - t_adv_);
    const double tau = std::min(c_.advection_time, std::max(t - t_adv0_, 0.0));
    v_adv_ += (v - v_adv_) * dt / (tau + dt);
  }
  t_adv_ = t;
  while (history_.size() > 2 && history_.front()[0] < t - c_.max_delay) history_.pop_front();
  return restart;
}

bool LidarLoadModel::moments(double t, double rotor_speed, double azimuth, const std::array<double, 3>& pitch,
                             std::array<double, 3>& m) {
  if (history_.empty() || !have_adv_ || table_ == nullptr || table_->empty()) return false;
  // Frozen turbulence: what the LIDAR measured D / V ago reaches the rotor now.
  const double want = t - c_.lidar_distance / std::max(v_adv_, 1.0);
  while (history_.size() > 1 && history_[1][0] <= want) history_.pop_front();
  const auto& e = history_.front();
  if (e[0] > want || want - e[0] > c_.max_lidar_age) return false;
  const double h = c_.hub_height, r = c_.lidar_half_span * c_.rotor_radius;
  const double vu = e[1], vl = e[2];
  // Power-law shear through the two beams, then each blade's wind at its height (Figure 1).
  const ShearProfile profile = shear_from_beams(vu, vl, h, r);
  alpha_ = profile.exponent;
  v_hub_ = profile.hub_speed;
  lambda_ = rotor_speed * c_.rotor_radius / v_hub_;  // eq 1 at the hub speed (the rotor's operating point)
  const double rl = c_.load_radius * c_.rotor_radius;
  for (int i = 0; i < 3; ++i) {
    const double psi = azimuth + i * 2.0 * M_PI / 3.0;
    const double dev = std::remainder(psi - M_PI, 2.0 * M_PI) / c_.shadow_width;
    const double shadow = 1.0 - c_.tower_shadow * std::exp(-dev * dev);
    const double vi = profile.at(h + rl * std::cos(psi)) * shadow;
    m[i] = table_->k(lambda_, pitch[i]) * vi * vi;  // eq 9
  }
  return true;
}

}  // namespace windfdi::blade_load
