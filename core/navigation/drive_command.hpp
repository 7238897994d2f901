#pragma once

namespace strata {

/// What a motion controller asks of a differential-drive base: forward speed v (m/s), turn rate w (rad/s).
/// Core's own type: the drivers translate it for their base.
struct DriveCommand {
  double v = 0.0;
  double w = 0.0;
  /// An operator drives by hand (teleop): a stop-and-go base scans when they let go, not under them.
  bool by_hand = false;
};

}  // namespace strata
