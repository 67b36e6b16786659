// What a diagnostic service does with each of a turbine's measured inputs, and what it cannot do without
// them.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace windfdi {

/// One use a service makes of the measured inputs (replay columns, frame_sample.hpp's channels).
struct InputUse {
  std::string purpose;               ///< what the service does with them
  std::vector<std::string> columns;  ///< every one of them is needed (replay column names)
  bool essential = true;             ///< false: an aid; the service works without it, less well
  std::string without;               ///< what is not done (or done instead) without them
};

/// One use per blade from a pattern: each column name gets "_1".."_3", and "{blade}" in the purpose and in
/// `without` becomes the blade's number.
std::vector<InputUse> per_blade(const InputUse& pattern);

/// A turbine's inputs against a service's uses; `present(column)`: the data carries that column at all (a
/// recording's header, or a value seen on DDS). Absent is not invalid: an absent input is a use the
/// service does without, said once at start, not a stream of rejected samples.
struct InputCheck {
  std::vector<std::string> present;  ///< the columns of the uses the data carries
  std::vector<std::string> lines;    ///< one per use it lacks: "lacks pitch_1 (...): ..."
  bool any_essential = false;        ///< at least one essential use is possible
  std::vector<std::string> missing;  ///< the columns the essential uses lack (for the error)
};
InputCheck check_inputs(const std::vector<InputUse>& uses,
                        const std::function<bool(const std::string&)>& present);

/// Logs the check for `source` (a file or "turbine WT01"). When no essential use is possible (the service has
/// nothing to diagnose there): `fatal` throws ConfigError(source, line 1, the missing columns), else logs an
/// error.
void report_inputs(const std::string& service, const std::vector<InputUse>& uses,
                   const std::function<bool(const std::string&)>& present, const std::string& source,
                   bool fatal);

}  // namespace windfdi
