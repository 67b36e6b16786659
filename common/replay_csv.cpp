// The replay format: FrameSample rows in CSV.
#include "replay_csv.hpp"

#include <cmath>

#include "yaml_config.hpp"

namespace windfdi {

namespace {

// One entry per replay column: its name, where it lives in FrameSample, and its valid bit.
struct ColumnSpec {
  const char* name;
  double FrameSample::*scalar;
  std::array<double, kBlades> FrameSample::*blades;
  int blade;
  uint32_t valid_bit;
};

const std::vector<ColumnSpec>& specs() {
  static const std::vector<ColumnSpec> s = {
      {"rotor_speed", &FrameSample::rotor_speed, nullptr, 0, kValidRotorSpeed},
      {"generator_speed", &FrameSample::generator_speed, nullptr, 0, kValidGeneratorSpeed},
      {"aero_torque", &FrameSample::aero_torque, nullptr, 0, 0},
      {"gen_torque", &FrameSample::gen_torque, nullptr, 0, kValidGenTorque},
      {"gen_torque_ref", &FrameSample::gen_torque_ref, nullptr, 0, 0},
      {"power", &FrameSample::power, nullptr, 0, kValidPower},
      {"aero_power", &FrameSample::aero_power, nullptr, 0, 0},
      {"wind_hub", &FrameSample::wind_hub, nullptr, 0, kValidWindHub},
      {"azimuth", &FrameSample::azimuth, nullptr, 0, kValidAzimuth},
      {"pitch_1", nullptr, &FrameSample::pitch, 0, kValidPitch1},
      {"pitch_2", nullptr, &FrameSample::pitch, 1, kValidPitch1 << 1},
      {"pitch_3", nullptr, &FrameSample::pitch, 2, kValidPitch1 << 2},
      {"pitch_ref_1", nullptr, &FrameSample::pitch_ref, 0, kValidPitchRef1},
      {"pitch_ref_2", nullptr, &FrameSample::pitch_ref, 1, kValidPitchRef1 << 1},
      {"pitch_ref_3", nullptr, &FrameSample::pitch_ref, 2, kValidPitchRef1 << 2},
      {"blade_moment_1", nullptr, &FrameSample::blade_moment, 0, kValidBladeMoment1},
      {"blade_moment_2", nullptr, &FrameSample::blade_moment, 1, kValidBladeMoment1 << 1},
      {"blade_moment_3", nullptr, &FrameSample::blade_moment, 2, kValidBladeMoment1 << 2},
      {"lidar_v_upper", &FrameSample::lidar_v_upper, nullptr, 0, kValidLidar},
      {"lidar_v_lower", &FrameSample::lidar_v_lower, nullptr, 0, kValidLidar},
  };
  return s;
}

double& field(FrameSample& s, const ColumnSpec& c) { return c.scalar ? s.*c.scalar : (s.*c.blades)[c.blade]; }
double field(const FrameSample& s, const ColumnSpec& c) {
  return c.scalar ? s.*c.scalar : (s.*c.blades)[c.blade];
}

}  // namespace

const std::vector<std::string>& replay_columns() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& c : specs()) n.emplace_back(c.name);
    return n;
  }();
  return names;
}

uint32_t valid_bit(const std::string& column) {
  for (const auto& c : specs())
    if (column == c.name) return c.valid_bit;
  return 0;
}

uint32_t absent_channels(const std::function<bool(const std::string&)>& has_column) {
  uint32_t absent = 0;
  for (const auto& c : specs())
    if (c.valid_bit != 0 && !has_column(c.name)) absent |= c.valid_bit;
  return absent;
}

uint32_t channels_with_values(const FrameSample& s) {
  uint32_t present = 0;
  for (const auto& c : specs())
    if (c.valid_bit != 0 && (s.valid_mask & c.valid_bit) && std::isfinite(field(s, c)))
      present |= c.valid_bit;
  return present;
}

FrameCsvReader::FrameCsvReader(const std::string& path)
    : csv_(path),
      col_t_(csv_.column("t")),
      col_turbine_(csv_.column("turbine_id")),
      col_sequence_(csv_.column("sequence")) {
  if (col_t_ < 0) throw ConfigError(path, 1, "t", "required column is missing from the header");
  for (const auto& c : specs()) cols_.push_back(csv_.column(c.name));
}

bool FrameCsvReader::next(FrameSample& s, std::string& turbine_id) {
  if (!csv_.next()) return false;
  s = FrameSample{};
  s.valid_mask = kValidAll;
  s.t = csv_.number(col_t_);
  if (!std::isfinite(s.t)) throw ConfigError(csv_.path(), csv_.line(), "t", "time must be a finite number");
  turbine_id = col_turbine_ >= 0 ? csv_.text(col_turbine_) : std::string("WT01");
  if (turbine_id.empty()) throw ConfigError(csv_.path(), csv_.line(), "turbine_id", "empty turbine id");
  const auto& sp = specs();
  for (std::size_t i = 0; i < sp.size(); ++i) {
    const double v = cols_[i] >= 0 ? csv_.number(cols_[i]) : kNaN;
    field(s, sp[i]) = v;
    if (!std::isfinite(v)) s.valid_mask &= ~sp[i].valid_bit;
  }
  auto it = next_sequence_.begin();
  while (it != next_sequence_.end() && it->first != turbine_id) ++it;
  if (it == next_sequence_.end()) it = next_sequence_.insert(it, {turbine_id, 0});
  if (col_sequence_ >= 0) {
    const double q = csv_.number(col_sequence_);
    if (!(q >= 0) || q != std::floor(q))
      throw ConfigError(csv_.path(), csv_.line(), "sequence", "must be a non-negative integer");
    s.sequence = static_cast<uint64_t>(q);
  } else {
    s.sequence = it->second;
  }
  it->second = s.sequence + 1;
  return true;
}

namespace {
std::vector<std::string> writer_header(const std::vector<std::string>& extra) {
  std::vector<std::string> h = {"t", "turbine_id", "sequence"};
  h.insert(h.end(), replay_columns().begin(), replay_columns().end());
  h.insert(h.end(), extra.begin(), extra.end());
  return h;
}
}  // namespace

FrameCsvWriter::FrameCsvWriter(const std::string& path, const std::vector<std::string>& extra_columns)
    : csv_(path, writer_header(extra_columns)), extra_columns_(extra_columns.size()) {}

void FrameCsvWriter::write(const std::string& turbine_id, const FrameSample& s,
                           const std::vector<double>& extra) {
  if (extra.size() != extra_columns_) throw std::logic_error("FrameCsvWriter: wrong number of extra values");
  csv_.add(s.t).add(turbine_id).add(std::to_string(s.sequence));
  for (const auto& c : specs()) csv_.add(field(s, c));
  for (double v : extra) csv_.add(v);
  csv_.end_row();
}

}  // namespace windfdi
