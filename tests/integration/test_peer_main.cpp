// windfdi-test-peer: a DDS peer for the multi-process tests (publishes or receives TurbineFrames).
#include <spdlog/spdlog.h>

#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "app.hpp"
#include "dds/convert.hpp"
#include "dds/endpoints.hpp"

using namespace windfdi;

namespace {

int publish(const CommonOptions& common, const std::vector<std::string>& ids, int blocks, int block_size,
            int readers, double rate) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer"));
  bus::Writer<windfdi::TurbineFrame> writer(participant);
  if (!writer.wait_for_readers(readers, std::chrono::seconds(20))) {
    spdlog::error("only {} of {} readers matched", writer.matched(), readers);
    return 1;
  }
  std::map<std::string, uint64_t> sequence;
  int failures = 0;
  for (int b = 0; b < blocks && !shutdown_requested(); ++b) {
    for (const auto& id : ids) {
      windfdi::TurbineFrame frame;
      frame.turbine_id(id);
      for (int k = 0; k < block_size; ++k) {
        FrameSample s;
        s.sequence = sequence[id]++;
        s.t = 0.01 * static_cast<double>(s.sequence);
        s.rotor_speed = 1.2;
        frame.samples().push_back(bus::to_idl(s));
      }
      frame.t(frame.samples().back().t());
      if (!writer.write(frame)) ++failures;
    }
    sleep_unless_shutdown(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(1.0 / rate)));
  }
  writer.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0));
  std::cout << nlohmann::json{{"published_blocks", blocks}, {"write_failures", failures}}.dump() << std::endl;
  return failures == 0 ? 0 : 1;
}

int listen(const CommonOptions& common, uint64_t expect, double timeout) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer"));
  bus::Wakeup wakeup;
  bus::Reader<windfdi::TurbineFrame> reader(participant, common.turbines, &wakeup);
  std::map<std::string, uint64_t> count, gaps, next;
  uint64_t total = 0;
  const double start = wall_time();
  std::vector<windfdi::TurbineFrame> frames;
  // Ready marker: the test waits for it before starting the publisher.
  std::cout << "{\"ready\":true}" << std::endl;
  while (!shutdown_requested() && total < expect && wall_time() - start < timeout) {
    wakeup.wait_for(std::chrono::milliseconds(100));
    frames.clear();
    reader.take(frames);
    for (const auto& f : frames) {
      for (const auto& s : f.samples()) {
        const std::string& id = f.turbine_id();
        if (next.count(id) && s.sequence() != next[id]) gaps[id] += s.sequence() - next[id];
        next[id] = s.sequence() + 1;
        ++count[id];
        ++total;
      }
    }
  }
  nlohmann::json out{{"total", total}, {"counts", count}, {"gaps", gaps}};
  std::cout << out.dump() << std::endl;
  // Asked to stop (SIGTERM/SIGINT): a clean exit; otherwise success means everything expected arrived.
  return (shutdown_requested() || total >= expect) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DDS test peer: publishes or receives TurbineFrames", "windfdi-test-peer"};
  CommonOptions common;
  add_common_options(app, common);
  std::string mode = "listen";
  std::vector<std::string> ids = {"WT01", "WT02", "WT03"};
  int blocks = 100, block_size = 10, readers = 1;
  double rate = 100.0, timeout = 30.0;
  uint64_t expect = 0;
  app.add_option("mode", mode, "publish or listen")->check(CLI::IsMember({"publish", "listen"}));
  app.add_option("--ids", ids, "turbine ids to publish")->delimiter(',');
  app.add_option("--blocks", blocks, "blocks per turbine");
  app.add_option("--block", block_size, "samples per block (1..32)")->check(CLI::Range(1, 32));
  app.add_option("--readers", readers, "readers to wait for before publishing");
  app.add_option("--rate", rate, "blocks per second per turbine");
  app.add_option("--expect", expect, "samples to receive before exiting");
  app.add_option("--timeout", timeout, "seconds before giving up");
  return run_main(app, argc, argv, common, [&] {
    return mode == "publish" ? publish(common, ids, blocks, block_size, readers, rate) : listen(common, expect, timeout);
  });
}
