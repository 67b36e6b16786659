// What every windfdi executable shares: common command-line options, logging, signals, exit codes.
#include "app.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <thread>

#include "turbine_selection.hpp"
#include "version.hpp"
#include "yaml_config.hpp"

namespace windfdi {

namespace {
std::atomic<bool> g_shutdown{false};
extern "C" void on_signal(int) { g_shutdown = true; }
}  // namespace

void add_common_options(CLI::App& app, CommonOptions& o) {
  app.set_version_flag("--version", std::string("windfdi ") + kVersion);
  app.add_option("--domain", o.domain, "DDS domain id (0..232); default $WINDFDI_DOMAIN or 0");
  app.add_option(
         "--turbine", o.turbines,
         "serve only this turbine id, or the ids FIRST..LAST in byte order (repeatable; default: every "
         "turbine)")
      ->take_all()
      ->check(turbine_selection_error);
  app.add_option("--max-turbines", o.max_turbines,
                 "turbines this instance keeps state for, the first it hears of; messages naming others are "
                 "refused and counted (a peer on an unsecured domain can name any number)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}));
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error, critical or off")
      ->capture_default_str();
  app.add_option("--qos", o.qos_file, "Fast DDS XML QoS profile file (default deploy/qos/windfdi_qos.xml)");
  app.add_option("--participant-profile", o.participant_profile,
                 "participant profile in the QoS file (default $WINDFDI_PARTICIPANT_PROFILE or "
                 "windfdi_participant)");
  app.add_option("--security", o.security_dir,
                 "DDS-Security credentials directory (deploy/security/make_credentials.sh): authentication, "
                 "access control and encryption; the participant refuses to start without valid credentials");
  app.add_option("--security-role", o.security_role,
                 "role whose credentials to use (DIR/ROLE/); default: this executable's role");
}

int resolve_domain(int flag) {
  if (flag >= 0) {
    if (flag > 232) throw ConfigError("--domain", 0, "", "domain id must be in 0..232");
    return flag;
  }
  const char* env = std::getenv("WINDFDI_DOMAIN");
  if (!env || !*env) return 0;
  char* end = nullptr;
  const long d = std::strtol(env, &end, 10);
  if (*end != '\0' || d < 0 || d > 232)
    throw ConfigError("WINDFDI_DOMAIN", 0, "", std::string("'") + env + "' is not a domain id in 0..232");
  return static_cast<int>(d);
}

bus::ParticipantOptions participant_options(const CommonOptions& o, const std::string& name) {
  bus::ParticipantOptions p;
  p.domain = resolve_domain(o.domain);
  p.qos_file = o.qos_file;
  p.name = name;
  p.security_dir = o.security_dir;
  p.security_role = o.security_role;
  if (!o.participant_profile.empty()) {
    p.profile = o.participant_profile;
  } else if (const char* env = std::getenv("WINDFDI_PARTICIPANT_PROFILE"); env && *env) {
    p.profile = env;
  }
  return p;
}

void setup_logging(const std::string& level, const std::string& name) {
  const auto lvl = spdlog::level::from_str(level);
  if (lvl == spdlog::level::off && level != "off")
    throw ConfigError("--log-level", 0, "",
                      "'" + level +
                          "' is not one of trace, debug, info, warn, error, "
                          "critical, off");
  auto logger = spdlog::stderr_color_mt(name);
  spdlog::set_default_logger(logger);
  spdlog::set_level(lvl);
  spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %n %^%l%$: %v");
  spdlog::flush_on(spdlog::level::warn);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool shutdown_requested() { return g_shutdown.load(); }

bool sleep_unless_shutdown(std::chrono::nanoseconds d) {
  const auto end = std::chrono::steady_clock::now() + d;
  while (!g_shutdown) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= end) return true;
    std::this_thread::sleep_for(std::min<std::chrono::nanoseconds>(end - now, std::chrono::milliseconds(50)));
  }
  return false;
}

bool worth_logging(uint64_t count) {
  uint64_t power = 1;
  while (power <= count / 10) power *= 10;
  return count == power;
}

double wall_time() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

int run_main(CLI::App& app, int argc, char** argv, const CommonOptions& options,
             const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0.
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    setup_logging(options.log_level, app.get_name());
    install_signal_handlers();
    const int rc = body();
    spdlog::default_logger()->flush();
    return rc;
  } catch (const ConfigError& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << std::endl;
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": fatal: " << e.what() << std::endl;
    return kExitFailure;
  }
}

}  // namespace windfdi
