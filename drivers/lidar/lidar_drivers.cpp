#include "drivers/lidar/lidar_drivers.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <stdexcept>
#include <utility>

namespace strata::lidar {
namespace {

/// The odometry a lidar alone hands on: none, so a constant pose (see LidarDriverOptions).
RobotSample sample_at(double stamp) {
  RobotSample sample;
  sample.stamp = stamp;
  return sample;
}

void prepare(ScanEvent& scan, SensorMount& mount) {
  mount.apply(scan);
  scan.odometry = Pose3{};
  scan.has_odometry = false;
}

}  // namespace

std::string describe_counters(const LidarScanBuilder& builder) {
  const DecodeStats& decode = builder.decode_stats();
  const LidarScanBuilder::Stats& stats = builder.stats();
  return fmt::format(
      "{} packets decoded, {} skipped ({} wrong size, {} without a valid block, {} unsupported return mode), "
      "{} for another port, {} model mismatch, {} invalid blocks; {} complete revolutions, {} partial",
      decode.packets, decode.skipped(), decode.wrong_size, decode.no_valid_block, decode.unsupported_mode,
      stats.wrong_port, decode.model_mismatch, decode.invalid_blocks, stats.complete_revolutions,
      stats.partial_revolutions);
}

// --- PcapLidarDriver ---------------------------------------------------------------------------------

PcapLidarDriver::PcapLidarDriver(std::filesystem::path pcap, LidarDriverOptions options,
                                 PlaybackPacing pacing)
    : pcap_(std::move(pcap)),
      options_(std::move(options)),
      mount_(options_.sensor_to_base, "pcap"),
      clock_(pacing),
      source_(pcap_, options_.setup) {}

PcapLidarDriver::~PcapLidarDriver() {
  stop();
}

std::string PcapLidarDriver::description() const {
  return fmt::format("{} capture {}, no odometry (ICP alone tracks the motion), {}",
                     sensor_name(options_.setup.model), pcap_.string(), clock_.description());
}

void PcapLidarDriver::start(Outputs outputs) {
  if (thread_.joinable())
    return;
  thread_ = std::thread([this, outputs = std::move(outputs)]() mutable { run(std::move(outputs)); });
}

void PcapLidarDriver::stop() {
  clock_.stop();
  if (thread_.joinable())
    thread_.join();
}

void PcapLidarDriver::run(Outputs outputs) {
  std::size_t played = 0;
  try {
    while (std::optional<ScanEvent> scan = source_.next()) {
      if (clock_.stopped())
        return;
      prepare(*scan, mount_);
      if (!clock_.wait_until_due(scan->stamp))
        return;
      outputs.on_sample(sample_at(scan->stamp));
      outputs.on_scan(std::move(*scan));
      ++played;
      if (!clock_.wait_for_pipeline(outputs.wait_for_pipeline))
        return;
    }
  } catch (const std::exception& error) {
    // A capture that breaks off mid-way: what was played stays mapped.
    spdlog::error("pcap: {}: {}", pcap_.string(), error.what());
  }
  finished_ = true;
  if (outputs.on_finished)
    outputs.on_finished();
  const PcapStats& pcap = source_.pcap_stats();
  spdlog::info("pcap finished: {} scans played in {:.1f} s; serving the map", played,
               clock_.seconds_playing());
  spdlog::info("pcap: {} frames, {} UDP datagrams, {} skipped{}; decoder: {}", pcap.records, pcap.datagrams,
               pcap.skipped(), pcap.truncated_file ? " (the file ends inside a record)" : "",
               describe_counters(source_.builder()));
}

// --- LiveLidarDriver ---------------------------------------------------------------------------------

LiveLidarDriver::LiveLidarDriver(LidarDriverOptions options, const std::string& address,
                                 std::chrono::seconds counters_period)
    : options_(std::move(options)),
      mount_(options_.sensor_to_base, "lidar"),
      address_(address),
      counters_period_(counters_period),
      source_(io_, options_.setup, address),
      counters_timer_(io_) {}

LiveLidarDriver::~LiveLidarDriver() {
  stop();
}

std::string LiveLidarDriver::description() const {
  return fmt::format("live {} on UDP {}:{}, no odometry (ICP alone tracks the motion)",
                     sensor_name(options_.setup.model), address_, source_.port());
}

void LiveLidarDriver::start(Outputs outputs) {
  if (thread_.joinable())
    return;
  // Everything on the socket and the timer starts on the driver's own io thread, like all that follows.
  boost::asio::post(io_, [this, outputs = std::move(outputs)]() mutable {
    source_.start([this, outputs = std::move(outputs)](ScanEvent&& scan) {
      prepare(scan, mount_);
      ++scans_;
      outputs.on_sample(sample_at(scan.stamp));
      outputs.on_scan(std::move(scan));
    });
    schedule_counters();
  });
  thread_ = std::thread([this] { io_.run(); });
}

void LiveLidarDriver::schedule_counters() {
  counters_timer_.expires_after(counters_period_);
  counters_timer_.async_wait([this](const boost::system::error_code& error) {
    if (error)
      return;
    spdlog::info("lidar: {} scans, {} packets received; decoder: {}", scans_, source_.packets_received(),
                 describe_counters(source_.builder()));
    schedule_counters();
  });
}

void LiveLidarDriver::stop() {
  if (!thread_.joinable())
    return;
  boost::asio::post(io_, [this] {
    counters_timer_.cancel();
    source_.stop();
    spdlog::info("lidar stopped: {} scans, {} packets received; decoder: {}", scans_,
                 source_.packets_received(), describe_counters(source_.builder()));
    io_.stop();
  });
  thread_.join();
}

}  // namespace strata::lidar
