// Where the files shipped under deploy/ (turbine, QoS, gains, scenarios) are found: built or installed.
#pragma once

#include <string>

namespace windfdi {

/// The deploy directory: $WINDFDI_DEPLOY_DIR when set, else the source tree's deploy/ when it exists (a
/// build), else the installed configuration directory (/etc/windfdi). Named files live below it, e.g.
/// deploy_dir() + "/turbine/benchmark_4.8MW.yaml".
std::string deploy_dir();

}  // namespace windfdi
