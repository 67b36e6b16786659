// windfdi-farm: the farm monitor (live table, SQLite history, operator acknowledgements).
#include <cstdlib>

#include "app.hpp"
#include "farm_cli.hpp"
#include "farm_node.hpp"

int main(int argc, char** argv) {
  using namespace windfdi;
  CLI::App app{"Farm monitor: follows every turbine's faults, stores them, acknowledges them",
               "windfdi-farm"};
  CommonOptions common;
  add_common_options(app, common);
  farm::FarmOptions options;
  if (const char* db = std::getenv("WINDFDI_FARM_DB"); db && *db) options.db = db;
  app.add_option("--db", options.db, "SQLite database (default $WINDFDI_FARM_DB or ./windfdi-farm.sqlite)")
      ->capture_default_str();
  app.add_option("--table-period", options.table_period, "seconds between live tables (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--estimate-period", options.estimate_period,
                 "seconds of estimate time between the estimates stored per turbine and service (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  app.add_option("--estimate-retention", options.estimate_retention, "hours the stored estimates are kept")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 24.0 * 3650));
  app.add_option("--http", options.http.listen,
                 "serve the web page, JSON API and /metrics on PORT (127.0.0.1) or ADDR:PORT (default: off)");
  if (const char* token = std::getenv("WINDFDI_FARM_TOKEN_FILE"); token && *token)
    options.http.token_file = token;
  app.add_option("--http-token-file", options.http.token_file,
                 "file holding the operator token (acknowledgements, remote access; default "
                 "$WINDFDI_FARM_TOKEN_FILE, none: read-only on localhost)");
  app.add_option("--report-scenario", options.report_scenario,
                 "the plant scenario this farm runs: the page and GET /api/report judge the run against it");
  app.add_option("--http-cert", options.http.cert,
                 "PEM certificate: HTTPS instead of HTTP (with --http-key)");
  app.add_option("--http-key", options.http.key, "PEM private key of --http-cert");

  auto* history = app.add_subcommand("history", "print the stored events");
  std::string turbine;
  double since = 0.0;
  bool json = false;
  history->add_option("--turbine", turbine, "only this turbine");
  history->add_option("--since", since, "only events received at or after this Unix time (s)");
  history->add_flag("--json", json, "JSON Lines instead of a table");

  auto* ack = app.add_subcommand("ack", "acknowledge a latched fault (publishes a FaultAck)");
  std::string ack_turbine, component, fault = "none", operator_name = "operator";
  double timeout = 5.0;
  ack->add_option("TURBINE", ack_turbine, "turbine id")->required();
  ack->add_option("COMPONENT", component, "component, e.g. pitch_actuator_3")->required();
  ack->add_option("--fault", fault, "fault class (default: every class on the component)")
      ->capture_default_str();
  ack->add_option("--operator", operator_name, "who acknowledges")->capture_default_str();
  ack->add_option("--timeout", timeout, "seconds to wait for an arbiter")->capture_default_str();

  auto* report = app.add_subcommand("report", "injected faults of a scenario against the stored detections");
  std::string scenario;
  report->add_option("--scenario", scenario, "the plant scenario that was run")->required();
  report->add_option("--since", since, "only events received at or after this Unix time (s)");
  std::string history_file;
  report->add_option(
      "--history", history_file,
      "report on a history file (windfdi-farm history --json, or system_replay) instead of --db");
  bool report_json = false;
  report->add_flag("--json", report_json,
                   "one JSON object (faults, extra reports, safe stops) instead of tables");

  return run_main(app, argc, argv, common, [&] {
    if (*report) return farm::print_report(options.db, scenario, since, history_file, report_json);
    if (*history) return farm::print_history(options.db, turbine, since, json);
    if (*ack) return farm::publish_ack(common, ack_turbine, component, fault, operator_name, timeout);
    farm::FarmNode(common, options).run();
    return kExitOk;
  });
}
