// The farm monitor's one-shot subcommands (the command line of main.cpp): ack, history, report.
#pragma once

#include <string>

#include "FaultAck.h"
#include "app.hpp"

namespace windfdi::farm {

/// The FaultAck of an operator's acknowledgement ("none": every class on the component); throws ConfigError
/// naming `key` when the fault class or the component is not known.
windfdi::FaultAck make_ack(const std::string& turbine, const std::string& component, const std::string& fault,
                           const std::string& operator_name, const std::string& key);

/// Publishes one FaultAck and waits (up to `timeout_s`) for it to be acknowledged by the readers.
int publish_ack(const CommonOptions& common, const std::string& turbine, const std::string& component,
                const std::string& fault, const std::string& operator_name, double timeout_s);

/// Prints injected faults against detections (ends the demo).
/// `history_file` (JSON Lines of `history --json`) instead of the database when given.
/// `json`: one JSON object (faults, extra reports, stops) instead of the tables.
int print_report(const std::string& db, const std::string& scenario, double since,
                 const std::string& history_file, bool json);

/// Prints the stored history (a table, or JSON Lines with `json`).
int print_history(const std::string& db, const std::string& turbine, double since, bool json);

}  // namespace windfdi::farm
