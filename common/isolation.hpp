// Turbine-level fault isolation: which of one turbine's fault reports a single root cause explains.
// The arbiter acts on roots only and the farm monitor marks the rest secondary; both use this pure core.
#pragma once

#include <string>
#include <vector>

namespace windfdi::isolation {

/// One row of the fault-signature table: a root-cause fault and one residual that responds to it.
/// Component patterns: an exact name; a name ending in "_*" (any blade); or ending in "_i" (a blade
/// component whose blade is bound by the other side of the row: pitch_sensor_i explains pitch_actuator_i).
struct Signature {
  const char* root_component;
  const char* root_classes;      ///< "*" or a comma-separated list of fault classes
  const char* responder_source;  ///< the service whose residual responds
  const char* responder_component;
  const char* why;  ///< the physical path, for the report's "explained by" detail
  /// s the responder may be detected before its root by this row (0: IsolationConfig::lead). A slow root
  /// (ice, confirmed by its inertia after minutes) explains a fast responder that saw it first.
  double lead = 0.0;
  /// Where this row and the reverse one both hold (each report explains the other), this row's root wins
  /// even when it was detected after its responder (evidence the reverse path cannot produce).
  bool outranks = false;
  /// s after its root within which a responder is this row's echo (0: any time while both stand). A
  /// responder that stops taking the root's input once the root is reported (drive_train's balance moves to
  /// the rotor's speed sensor) is its own root when it is raised later than that.
  double trail = 0.0;
};

/// The table (documented in deploy/arbiter/DECISION_TABLE.md "Isolation"; every row is a unit test).
const std::vector<Signature>& signature_table();

/// One report of one turbine as isolation sees it.
struct Report {
  std::string source;
  std::string component;
  std::string fault;
  double t_detected = 0.0;  ///< s, when its service first saw it
};

struct Verdict {
  bool secondary = false;
  std::string explained_by;  ///< "rotor_speed_sensor sensor_bias", or "common cause on every blade"
  std::string why;           ///< the signature row's physical path
};

struct IsolationConfig {
  /// s a responding residual may be detected before its root (services differ in speed: blade_load can
  /// confirm within a revolution, sensor_bias needs 1 s, pitch_diag 3 s)
  double lead = 15.0;
  /// s within which the same class on every blade's sensor is one common cause, not three sensor faults
  double common_window = 30.0;
};

/// The verdict for each report (same order). A report is secondary when another report explains it by a
/// table row and did not itself follow it: two reports that explain each other (a pitch sensor and its
/// actuator) are decided by which was detected first, a sensor winning a tie.
std::vector<Verdict> isolate(const std::vector<Report>& reports, const IsolationConfig& config = {});

/// The longest time any row lets a responder precede its root (s): reports that far apart must be isolated
/// together.
double longest_lead(const IsolationConfig& config = {});

/// True when a row of the table says that `root` explains `responder` (blades bound where the row says so).
bool explains(const Report& root, const Report& responder);

}  // namespace windfdi::isolation
