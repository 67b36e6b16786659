// The farm web page in a real headless browser: plant, sensor_bias, pitch_diag, the arbiter and the farm
// monitor with --http on a private DDS domain; the page's rendered DOM must show the turbine's tile with the
// injected fault on it, plots with data and the scenario's report, and screenshots of the farm and turbine
// views are written.
#include <gtest/gtest.h>
#include <httplib.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// The headless browser setup.sh installs (Debian's chromium-headless-shell, or chromium).
std::string browser() {
  for (const char* name : {"/usr/bin/chromium-headless-shell", "/usr/bin/chromium"})
    if (std::filesystem::exists(name)) return name;
  return "";
}

// Renders `url` in the browser (its scripts run for `budget_ms` of virtual time); with `screenshot`, writes a
// PNG there instead of printing the DOM. Returns the DOM (or "").
std::string render(const std::string& url, const std::string& profile, const std::string& screenshot = "",
                   int budget_ms = 4000) {
  std::vector<std::string> argv = {browser(),
                                   "--no-sandbox",
                                   "--disable-gpu",
                                   "--hide-scrollbars",
                                   "--user-data-dir=" + profile,
                                   "--window-size=1400,1000",
                                   "--virtual-time-budget=" + std::to_string(budget_ms)};
  argv.push_back(screenshot.empty() ? "--dump-dom" : "--screenshot=" + screenshot);
  argv.push_back(url);
  ChildProcess chrome(argv, {{"HOME", profile}}, "browser");
  EXPECT_EQ(chrome.wait(std::chrono::seconds(60)), 0) << chrome.stderr_text();
  return chrome.stdout_text();
}

// The value of attribute `name` in the element whose id is `id` in a dumped DOM ("" none).
std::string attribute(const std::string& dom, const std::string& id, const std::string& name) {
  const auto at = dom.find("id=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const auto start = dom.rfind('<', at);
  const auto end = dom.find('>', at);
  const std::string tag = dom.substr(start, end - start);
  const auto a = tag.find(" " + name + "=\"");
  if (a == std::string::npos) return "";
  const auto v = a + name.size() + 3;
  return tag.substr(v, tag.find('"', v) - v);
}

TEST(FarmWeb, TheBrowserShowsTheTurbineTheFaultOnItsTileAndPlotsWithData) {
  ASSERT_FALSE(browser().empty())
      << "no headless browser: deploy/scripts/setup.sh installs chromium-headless-shell";
  const int domain = private_domain(23);
  const auto env = dds_env(domain);
  const std::string dir = temp_dir("farm_web_" + std::to_string(domain));
  const std::string scenario = kDeploy + "/scenarios/sensor_bias_pitch.yaml";
  ChildProcess farm({bin("windfdi-farm"), "--db", dir + "/farm.sqlite", "--table-period", "0", "--http", "0",
                     "--report-scenario", scenario},
                    env, "farm");
  ChildProcess arbiter({bin("windfdi-arbiter")}, env, "arbiter");
  ChildProcess bias({bin("windfdi-sensor-bias"), "--config", kDeploy + "/config/sensor_bias.yaml"}, env,
                    "sensor_bias");
  ChildProcess pitch({bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"}, env,
                     "pitch_diag");
  const int port = farm_http_port(farm);
  ASSERT_GT(port, 0) << farm.stderr_text();
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the services discover each other
  // GIVEN the plant with a 1 deg pitch-sensor bias on blade 2 from 150 s, at 20x
  ChildProcess plant({bin("windfdi-plant"), "--scenario", scenario, "--rate", "20"}, env, "plant");
  // WHEN the farm monitor has the report and a few estimates of both services
  httplib::Client web("127.0.0.1", port);
  const auto fault_seen = [&] {
    const auto r = web.Get("/api/faults?turbine=WT01&component=pitch_sensor_2&state=raised");
    return r && r->status == 200 && !json::parse(r->body)["faults"].empty();
  };
  ASSERT_TRUE(wait_until(fault_seen, std::chrono::seconds(60))) << farm.stderr_text();
  for (const char* service : {"sensor_bias", "pitch_diag"}) {
    const auto r = web.Get(std::string("/api/estimates?turbine=WT01&service=") + service);
    ASSERT_TRUE(r && r->status == 200);
    EXPECT_GE(json::parse(r->body)["estimates"].size(), 5u) << service;
  }
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";

  // THEN the rendered farm view has WT01's tile, coloured by the fault, with the fault on it
  const std::string dom = render(url + "#turbine=WT01", dir + "/profile");
  ASSERT_NE(dom.find("id=\"tile-WT01\""), std::string::npos) << dom;
  EXPECT_EQ(attribute(dom, "tile-WT01", "data-severity"), "fault") << dom;
  const auto tile = dom.find("id=\"tile-WT01\"");
  const auto fault = dom.find("data-component=\"pitch_sensor_2\"", tile);
  EXPECT_NE(fault, std::string::npos) << dom;
  EXPECT_LT(fault, dom.find("id=\"alarms\"")) << "the fault is not on WT01's tile";
  // AND the alarm list holds it with an acknowledge button
  EXPECT_NE(dom.find("class=\"ack\" data-turbine=\"WT01\" data-component=\"pitch_sensor_2\""),
            std::string::npos);
  // AND the turbine view's plots were drawn from stored estimates (dygraphs' canvas inside)
  for (const char* plot : {"plot-bias-pitch", "plot-pitch-omega"}) {
    EXPECT_GE(std::atoi(attribute(dom, plot, "data-points").c_str()), 5) << plot;
    const auto at = dom.find(std::string("id=\"") + plot + "\"");
    const auto next = dom.find("class=\"plot\"", at + 1);
    EXPECT_NE(dom.substr(at, next - at).find("<canvas"), std::string::npos) << plot;
  }
  // AND the scenario report judges the run: the bias named right first
  EXPECT_NE(dom.find("<section id=\"report\">"), std::string::npos) << "the report section is hidden";
  const auto report = dom.find("id=\"report-faults\"");
  ASSERT_NE(report, std::string::npos);
  EXPECT_NE(dom.find("pitch_sensor_2 sensor_bias</td><td>sensor_bias", report), std::string::npos) << dom;
  // AND screenshots are written (WINDFDI_SCREENSHOT_DIR: where the README's come from)
  const char* shots = std::getenv("WINDFDI_SCREENSHOT_DIR");
  const std::string out = shots && *shots ? shots : dir;
  render(url, dir + "/profile", out + "/farm_view.png");
  render(url + "#turbine=WT01", dir + "/profile", out + "/turbine_view.png");
  for (const char* png : {"/farm_view.png", "/turbine_view.png"}) {
    ASSERT_TRUE(std::filesystem::exists(out + png)) << png;
    EXPECT_GT(std::filesystem::file_size(out + png), 10000u) << png;
  }
  plant.stop(SIGTERM);
  remove_stale_shm(domain);
}

}  // namespace
