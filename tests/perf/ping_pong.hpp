// Raw Fast DDS one-way latency, the baseline of the latency benchmarks: a ping writer and a pong echo.
#pragma once

#include <sys/types.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "TurbineFramePubSubTypes.h"
#include "app.hpp"
#include "dds/participant.hpp"

namespace windfdi::bench {

// A TurbineFrame writer on `out` and reader on `in`, both with the sensor_stream profile of wt/frame
// (reliable keep-last); `on_sample` runs in the reader's listener thread for every valid sample.
class PingEndpoints : public eprosima::fastdds::dds::DataReaderListener {
 public:
  PingEndpoints(bus::Participant& p, const std::string& out, const std::string& in,
                std::function<void(TurbineFrame&)> on_sample)
      : participant_(p), on_sample_(std::move(on_sample)) {
    using namespace eprosima::fastdds::dds;
    TypeSupport type(new TurbineFramePubSubType());
    Topic* t_out = p.topic(out, type);
    Topic* t_in = p.topic(in, type);
    DataWriterQos wq;
    DataReaderQos rq;
    if (p.publisher()->get_datawriter_qos_from_profile("sensor_stream", wq) != ReturnCode_t::RETCODE_OK ||
        p.subscriber()->get_datareader_qos_from_profile("sensor_stream", rq) != ReturnCode_t::RETCODE_OK)
      throw std::runtime_error("no sensor_stream profile");
    writer_ = p.publisher()->create_datawriter(t_out, wq);
    reader_ = p.subscriber()->create_datareader(t_in, rq, this, StatusMask::data_available());
    if (!writer_ || !reader_) throw std::runtime_error("cannot create the ping endpoints (permissions?)");
  }
  ~PingEndpoints() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
    participant_.publisher()->delete_datawriter(writer_);
  }
  PingEndpoints(const PingEndpoints&) = delete;
  PingEndpoints& operator=(const PingEndpoints&) = delete;

  bool matched() {
    eprosima::fastdds::dds::PublicationMatchedStatus ps;
    eprosima::fastdds::dds::SubscriptionMatchedStatus ss;
    writer_->get_publication_matched_status(ps);
    reader_->get_subscription_matched_status(ss);
    return ps.current_count > 0 && ss.current_count > 0;
  }
  bool write(TurbineFrame& f) { return writer_->write(&f); }

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader* r) override {
    TurbineFrame f;
    eprosima::fastdds::dds::SampleInfo info;
    while (r->take_next_sample(&f, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) on_sample_(f);
  }
  bus::Participant& participant_;
  std::function<void(TurbineFrame&)> on_sample_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
};

/// The echo process: writes every bench/ping sample back on bench/pong until SIGTERM.
inline int run_echo(const bus::ParticipantOptions& options) {
  install_signal_handlers();
  bus::Participant p(options);
  std::atomic<PingEndpoints*> self{nullptr};
  PingEndpoints e(p, "bench/pong", "bench/ping", [&](TurbineFrame& f) {
    if (PingEndpoints* s = self.load()) s->write(f);
  });
  self = &e;
  while (!shutdown_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return 0;
}

/// Starts `args` (args[0] the executable, no PATH search) as a child process; returns its pid.
inline pid_t spawn(std::vector<std::string> args) {
  const pid_t child = fork();
  if (child == 0) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(args[0].c_str(), argv.data());
    _exit(127);
  }
  return child;
}

}  // namespace windfdi::bench
