// Helpers every multi-process test uses: waiting for a condition, JSON lines of a peer's output, whole files.
#pragma once

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "process.hpp"

namespace windfdi::test {

/// Polls `pred` every `poll` until it holds or `timeout` has passed; checks once more at the end, so a slow
/// machine that meets the condition just in time still passes.
inline bool wait_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout,
                       std::chrono::milliseconds poll = std::chrono::milliseconds(100)) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(poll);
  }
  return pred();
}

/// The JSON objects among the lines of `text`; other lines (logs, a line cut short by a kill) are skipped.
inline std::vector<nlohmann::json> json_lines(const std::string& text) {
  std::vector<nlohmann::json> out;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) {
    if (line.empty() || line[0] != '{') continue;
    auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!j.is_discarded()) out.push_back(std::move(j));
  }
  return out;
}

/// A whole file as a string ("" when it does not exist).
inline std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Everything the farm monitor's database at `db` holds (`windfdi-farm history --json`), one object per
/// event; empty when the history command fails or hangs (it is given 20 s).
inline std::vector<nlohmann::json> farm_history(const std::string& db,
                                                const std::map<std::string, std::string>& env) {
  ChildProcess h({bin("windfdi-farm"), "--db", db, "history", "--json"}, env, "history");
  if (h.wait(std::chrono::seconds(20)) != 0) return {};
  return json_lines(h.stdout_text());
}

/// The port of a farm monitor started with `--http 0` (from its log line "API on http://127.0.0.1:PORT/"), 0
/// when it named none within 20 s.
inline int farm_http_port(ChildProcess& farm) {
  int port = 0;
  const std::string key = "API on http://127.0.0.1:";
  wait_until(
      [&] {
        const std::string err = farm.stderr_text();
        const auto at = err.find(key);
        if (at != std::string::npos) port = std::atoi(err.c_str() + at + key.size());
        return port > 0;
      },
      std::chrono::seconds(20));
  return port;
}

/// What a service said when it replayed a recording with a malformed third line.
struct MalformedReplay {
  int exit_code;
  std::string file;  ///< the recording's path, which the error must name
  std::string stderr_text;
};

/// Runs `<service_exe> --replay` on `csv` (a header and two rows, the second malformed) in a fresh temp dir.
inline MalformedReplay replay_malformed(const std::string& service_exe, const std::string& csv) {
  const std::string dir = temp_dir(service_exe + "_bad");
  std::ofstream(dir + "/bad.csv") << csv;
  ChildProcess p({bin(service_exe), "--replay", dir + "/bad.csv", "--estimates", dir + "/e.csv", "--events",
                  dir + "/e.jsonl"},
                 {}, service_exe + "_bad");
  const int code = p.wait(std::chrono::seconds(20));
  return {code, dir + "/bad.csv", p.stderr_text()};
}

}  // namespace windfdi::test
