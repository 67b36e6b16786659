// The installed package: `cmake --install` into a scratch root, then the plant and every diagnostic service
// run from what it installed alone (the configurations under etc/windfdi name ../turbine and ../sensor_bias).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include "test_util.hpp"

using namespace windfdi::test;
using namespace std::chrono_literals;

TEST(InstalledTree, ThePlantAndEveryServiceRunFromTheInstalledConfiguration) {
  const std::string root = temp_dir("install");
  ChildProcess install({WINDFDI_CMAKE, "--install", WINDFDI_BUILD_DIR, "--prefix", "/usr"},
                       {{"DESTDIR", root}}, "install");
  ASSERT_EQ(install.wait(180s), 0) << install.stdout_text() << install.stderr_text();

  // Every diagnostic service's systemd unit (generated from the registry) and the turbine target that wants
  // it.
  const std::string units = root + "/usr/lib/systemd/system/";
  const std::string target = read_file(units + "windfdi-turbine@.target");
  for (const std::string unit : {"blade-load", "sensor-bias", "pitch-diag", "ice-detect", "drive-train"}) {
    const std::string text = read_file(units + "windfdi-" + unit + "@.service");
    EXPECT_NE(text.find("ExecStart=/usr/bin/windfdi-" + unit + " --turbine %i"), std::string::npos) << unit;
    EXPECT_NE(target.find("windfdi-" + unit + "@%i.service"), std::string::npos) << unit;
  }

  const std::string etc = root + "/etc/windfdi";
  const std::string usr = root + "/usr";
  // The installed tree stands for /etc/windfdi: the source tree must not be what the binaries read.
  const std::map<std::string, std::string> env{{"WINDFDI_DEPLOY_DIR", etc}, {"WINDFDI_QOS_FILE", ""}};
  const std::string recording = root + "/ice_accretion.csv";
  ChildProcess plant(
      {usr + "/bin/windfdi-plant", "--scenario", usr + "/share/windfdi/scenarios/ice_accretion.yaml",
       "--offline", "--record", recording, "--duration", "60", "--progress", "0"},
      env, "plant");
  ASSERT_EQ(plant.wait(120s), 0) << plant.stderr_text();

  for (const std::string service : {"blade_load", "sensor_bias", "pitch_diag", "ice_detect", "drive_train"}) {
    std::string exe = "windfdi-" + service;
    std::replace(exe.begin(), exe.end(), '_', '-');
    const std::string estimates = root + "/" + service + ".csv";
    ChildProcess p({usr + "/bin/" + exe, "--config", etc + "/config/" + service + ".yaml", "--replay",
                    recording, "--estimates", estimates, "--events", root + "/" + service + ".jsonl"},
                   env, service);
    EXPECT_EQ(p.wait(120s), 0) << service << ": " << p.stderr_text();
    // A header and at least one estimate per simulated 10 s (ice_detect writes at 1 Hz, the slowest).
    const std::string text = read_file(estimates);
    EXPECT_GT(std::count(text.begin(), text.end(), '\n'), 6) << service;
  }
}
