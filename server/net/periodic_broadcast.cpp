#include "server/net/periodic_broadcast.hpp"

#include <boost/asio/post.hpp>
#include <stdexcept>
#include <utility>

namespace strata::net {

PeriodicBroadcast::PeriodicBroadcast(boost::asio::io_context& io, streams::ClientHub& hub, double rate_hz,
                                     Encoder encoder)
    : timer_(io), hub_(hub), encoder_(std::move(encoder)) {
  if (!(rate_hz > 0.0 && rate_hz <= 1000.0))
    throw std::invalid_argument("broadcast rate must be in (0, 1000] Hz");
  period_ = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz));
}

void PeriodicBroadcast::start() {
  running_ = true;
  timer_.expires_after(period_);
  schedule();
}

void PeriodicBroadcast::stop() {
  boost::asio::post(timer_.get_executor(), [self = shared_from_this()] {
    self->running_ = false;
    self->timer_.cancel();
  });
}

void PeriodicBroadcast::schedule() {
  timer_.async_wait([self = shared_from_this()](boost::system::error_code error) {
    if (error || !self->running_)
      return;
    for (const auto& message : self->encoder_())
      self->hub_.broadcast(message);
    // Fixed-rate schedule: the next tick is one period after the previous deadline, not after now.
    self->timer_.expires_at(self->timer_.expiry() + self->period_);
    self->schedule();
  });
}

}  // namespace strata::net
