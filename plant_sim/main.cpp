// windfdi-plant: the benchmark turbine simulator (one process, any number of turbines).
#include "app.hpp"
#include "plant_node.hpp"

int main(int argc, char** argv) {
  using namespace windfdi;
  CLI::App app{"Benchmark wind turbine simulator: publishes wt/frame and wt/lidar, applies wt/control/config",
               "windfdi-plant"};
  CommonOptions common;
  add_common_options(app, common);
  plant::PlantOptions o;
  std::string rate = "realtime";
  app.add_option("--scenario", o.scenario, "scenario YAML (see deploy/scenarios/)")->required();
  auto* rate_option = app.add_option(
      "--rate", rate, "realtime, max, or a speed-up factor (default: realtime, max with --offline)");
  app.add_flag("--offline", o.offline, "no DDS: simulate and record only");
  app.add_option("--record", o.record, "write the replay CSV (.gz to compress)");
  app.add_flag("--record-truth", o.record_truth, "add true values and active faults to the recording");
  app.add_option("--block", o.block, "samples per TurbineFrame (1..32)")->capture_default_str();
  app.add_option("--duration", o.duration, "simulated seconds (overrides the scenario)");
  app.add_option("--config-lease", o.config_lease, "seconds a control configuration stays valid unrefreshed")
      ->capture_default_str();
  app.add_option("--progress", o.progress_period, "seconds between progress lines (0: none)")
      ->capture_default_str();
  std::vector<std::string> clock_steps;
  app.add_option("--clock-step", clock_steps,
                 "AT:SECONDS: from simulated time AT on, the turbine controller's clock (the samples' time "
                 "stamps) is SECONDS ahead, negative: behind (an NTP step; repeatable, the steps add up)");
  return run_main(app, argc, argv, common, [&] {
    o.clock_steps = plant::parse_clock_steps(clock_steps);
    // Offline nothing waits for the simulation, so it runs as fast as it can unless told otherwise.
    o.rate = plant::parse_rate(o.offline && rate_option->count() == 0 ? "max" : rate);
    return plant::run_plant(common, o);
  });
}
