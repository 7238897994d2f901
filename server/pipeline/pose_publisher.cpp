#include "server/pipeline/pose_publisher.hpp"

#include <boost/asio/post.hpp>
#include <stdexcept>

#include "server/protocol/messages.hpp"

namespace strata::pipeline {

PosePublisher::PosePublisher(boost::asio::io_context& io, const RobotState& robot, net::ClientHub& hub,
                             double rate_hz)
    : timer_(io), robot_(robot), hub_(hub) {
  if (!(rate_hz > 0.0 && rate_hz <= 1000.0))
    throw std::invalid_argument("pose rate must be in (0, 1000] Hz");
  period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz));
}

void PosePublisher::start() {
  running_ = true;
  timer_.expires_after(period_);
  schedule();
}

void PosePublisher::stop() {
  boost::asio::post(timer_.get_executor(), [self = shared_from_this()] {
    self->running_ = false;
    self->timer_.cancel();
  });
}

void PosePublisher::schedule() {
  timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (error || !self->running_)
      return;
    self->publish();
    // Fixed-rate schedule: the next tick is one period after the previous deadline, not after now.
    self->timer_.expires_at(self->timer_.expiry() + self->period_);
    self->schedule();
  });
}

void PosePublisher::publish() {
  const auto sample = robot_.latest();
  if (!sample || sample->stamp == last_stamp_)
    return;  // nothing new since the last tick
  last_stamp_ = sample->stamp;
  hub_.broadcast(net::OutgoingMessage::text(protocol::pose_message(*sample), "pose"));
}

}  // namespace strata::pipeline
