// What every windfdi executable shares: common command-line options, logging, signals, exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dds/participant.hpp"
#include "turbine_limit.hpp"

namespace windfdi {

/// Exit codes: 0 success, 1 runtime failure, 2 bad configuration or input (file, line and key named).
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;

struct CommonOptions {
  int domain = -1;                    ///< --domain; -1: $WINDFDI_DOMAIN, else 0
  std::vector<std::string> turbines;  ///< --turbine (repeatable); empty: every turbine
  std::size_t max_turbines =
      kDefaultMaxTurbines;          ///< --max-turbines: turbines followed at most (TurbineLimit)
  std::string log_level = "info";   ///< --log-level
  std::string qos_file;             ///< --qos; empty: see bus::resolve_qos_file
  std::string participant_profile;  ///< --participant-profile; empty: $WINDFDI_PARTICIPANT_PROFILE or default
  std::string security_dir;         ///< --security DIR: DDS-Security credentials (deploy/security/)
  std::string security_role;        ///< --security-role; empty: the executable's own role
};

/// Adds --domain, --turbine, --max-turbines, --log-level, --qos, --participant-profile, --security,
/// --security-role and
/// --version.
void add_common_options(CLI::App& app, CommonOptions& options);

/// The domain id: the flag when given, else $WINDFDI_DOMAIN, else 0. A bad value is a ConfigError.
int resolve_domain(int flag);
bus::ParticipantOptions participant_options(const CommonOptions& options, const std::string& name);

/// Configures spdlog (stderr, with the executable's name); throws ConfigError for an unknown level.
void setup_logging(const std::string& level, const std::string& name);

/// SIGINT and SIGTERM request a graceful shutdown (entities deleted, logs flushed, no shm leftovers).
void install_signal_handlers();
bool shutdown_requested();
/// Sleeps up to `d`, returning early (false) when shutdown is requested.
bool sleep_unless_shutdown(std::chrono::nanoseconds d);

/// True at the 1st, 10th, 100th... occurrence of something counted: a flood of bad input is said in the log,
/// not echoed line by line.
bool worth_logging(uint64_t count);

/// Wall-clock time (s since the Unix epoch).
double wall_time();

/// Parses the command line, sets up logging and signals, runs `body`, and maps errors to exit codes:
/// CLI errors and ConfigError give 2 with the message on stderr, other exceptions 1.
int run_main(CLI::App& app, int argc, char** argv, const CommonOptions& options,
             const std::function<int()>& body);

}  // namespace windfdi
