#include "drivers/replay/recorder.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <stdexcept>
#include <utility>

#include "drivers/replay/layout_writer.hpp"

namespace strata::replay {
namespace fs = std::filesystem;

Recorder::Recorder(std::unique_ptr<RecordingWriter> writer, Limits limits)
    : writer_(std::move(writer)), limits_(limits) {
  thread_ = std::thread([this] { run(); });
}

Recorder::Recorder(fs::path directory, const nlohmann::json& metadata,
                   const Eigen::Isometry3d& initial_map_from_odom, Limits limits)
    : Recorder(std::make_unique<LayoutWriter>(std::move(directory), metadata, initial_map_from_odom),
               limits) {}

Recorder::~Recorder() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable())
    thread_.join();
  const RecorderStatus s = status();
  try {
    writer_->finish(s);
  } catch (const std::exception& e) {
    spdlog::error("recording: {}", e.what());
  }
  spdlog::info(
      "recording in {}: {} scans, {} odometry samples, {} other messages, {} dropped, {} write errors",
      writer_->where(), s.scans, s.samples, s.messages, s.dropped, s.errors);
}

void Recorder::record(const RobotSample& sample) {
  {
    std::lock_guard lock(mutex_);
    if (queued_samples_ >= limits_.queued_samples) {
      ++status_.dropped;
      return;
    }
    ++queued_samples_;
    queue_.emplace_back(sample);
  }
  wake_.notify_one();
}

void Recorder::record(const ScanEvent& scan) {
  {
    std::lock_guard lock(mutex_);
    if (queued_scans_ >= limits_.queued_scans) {
      ++status_.dropped;
      if (status_.dropped == 1)
        spdlog::warn("recording: the disk falls behind, dropping (counted in recording.json)");
      return;
    }
    ++queued_scans_;
    queue_.emplace_back(scan);
  }
  wake_.notify_one();
}

void Recorder::record(TopicMessage message) {
  if (!writer_->keeps_topic_messages())
    return;
  {
    std::lock_guard lock(mutex_);
    if (queued_samples_ >= limits_.queued_samples)
      return;
    ++queued_samples_;
    queue_.emplace_back(std::move(message));
  }
  wake_.notify_one();
}

void Recorder::flush() {
  std::unique_lock lock(mutex_);
  drained_.wait(lock, [this] { return (queue_.empty() && !writing_) || !thread_.joinable(); });
}

RecorderStatus Recorder::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void Recorder::run() {
  while (true) {
    Item item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) {  // stopping, and everything is written
        drained_.notify_all();
        return;
      }
      item = std::move(queue_.front());
      queue_.pop_front();
      if (std::holds_alternative<ScanEvent>(item))
        --queued_scans_;
      else
        --queued_samples_;
      writing_ = true;
    }
    write(item);
    {
      std::lock_guard lock(mutex_);
      writing_ = false;
      if (queue_.empty())
        drained_.notify_all();
    }
  }
}

void Recorder::write(const Item& item) {
  try {
    std::visit([this](const auto& value) { writer_->write(value); }, item);
    std::lock_guard lock(mutex_);
    if (std::holds_alternative<ScanEvent>(item))
      ++status_.scans;
    else if (std::holds_alternative<RobotSample>(item))
      ++status_.samples;
    else
      ++status_.messages;
  } catch (const std::exception& e) {
    std::size_t errors = 0;
    {
      std::lock_guard lock(mutex_);
      errors = ++status_.errors;
    }
    if (errors <= 10)  // a full disk fails every write: the first few say why
      spdlog::error("recording: {}", e.what());
  }
}

}  // namespace strata::replay
