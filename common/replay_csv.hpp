// The replay format (docs/architecture.md "Replay: the offline contract"): FrameSample rows in CSV.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "csv.hpp"
#include "frame_sample.hpp"

namespace windfdi {

/// The measured columns of the replay format, in the order the plant writes them.
const std::vector<std::string>& replay_columns();

/// The valid bit (frame_sample.hpp) of a replay column; 0 for a column without one (aero_torque,
/// gen_torque_ref, aero_power: optional by nature, NaN when not given) or an unknown name.
uint32_t valid_bit(const std::string& column);

/// Valid bits of the measured channels a recording's header lacks (`has_column`): absent, not invalid.
uint32_t absent_channels(const std::function<bool(const std::string&)>& has_column);

/// Valid bits of the channels a sample carries: marked valid and finite (what "present" means on DDS, where
/// every sample has every field).
uint32_t channels_with_values(const FrameSample& sample);

/// Reads FrameSamples from a replay CSV. Required: `t`; every other column is optional (a missing one
/// reads as NaN and clears its valid bit). Unknown columns are ignored. When there is no `sequence`
/// column, samples are numbered per turbine in file order.
class FrameCsvReader {
 public:
  explicit FrameCsvReader(const std::string& path);
  /// False at the end of the file. Throws ConfigError for a malformed row.
  bool next(FrameSample& sample, std::string& turbine_id);
  long line() const { return csv_.line(); }
  const std::string& path() const { return csv_.path(); }
  bool has_column(const std::string& name) const { return csv_.column(name) >= 0; }

 private:
  CsvReader csv_;
  int col_t_, col_turbine_, col_sequence_;
  std::vector<int> cols_;  // per replay_columns()
  std::vector<std::pair<std::string, uint64_t>> next_sequence_;
};

/// Writes FrameSamples in the replay format, plus any extra columns (e.g. the plant's `true_*`).
class FrameCsvWriter {
 public:
  FrameCsvWriter(const std::string& path, const std::vector<std::string>& extra_columns = {});
  /// `extra` must have one value per extra column.
  void write(const std::string& turbine_id, const FrameSample& sample, const std::vector<double>& extra = {});
  void flush() { csv_.flush(); }

 private:
  CsvWriter csv_;
  std::size_t extra_columns_;
};

}  // namespace windfdi
