// windfdi-arbiter: the fault-tolerant control arbiter (decision table: deploy/arbiter/DECISION_TABLE.md).
#include "app.hpp"
#include "arbiter_node.hpp"

int main(int argc, char** argv) {
  using namespace windfdi;
  CLI::App app{"Fault-tolerant control arbiter: faults in, one control configuration per turbine out",
               "windfdi-arbiter"};
  CommonOptions common;
  add_common_options(app, common);
  std::string config_file;
  arbiter::NodeOptions node;
  app.add_option("--config", config_file,
                 "arbiter YAML (default: built-in defaults, see deploy/config/arbiter.yaml)");
  app.add_option("--arbiter-id", node.arbiter_id, "name in every configuration published")
      ->capture_default_str();
  app.add_option("--strength", node.strength,
                 "ownership strength: the live arbiter with the highest is followed")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  app.add_flag("--shared-memory", node.shared_memory,
               "also use the QoS profile's shared-memory transport (default: UDP alone, which a stopped and "
               "resumed arbiter keeps; see services/arbiter/README.md \"Redundancy\")");
  return run_main(app, argc, argv, common, [&] {
    arbiter::ArbiterConfig config;
    if (!config_file.empty()) config = arbiter::load_arbiter_config(YamlSection::load_file(config_file));
    arbiter::ArbiterNode(common, config, node).run();
    return kExitOk;
  });
}
