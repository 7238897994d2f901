#pragma once

namespace strata {

/// What a motion controller asks of a differential-drive base: forward speed v (m/s), turn rate w (rad/s).
/// Core's own type: the drivers translate it for their base.
struct DriveCommand {
  double v = 0.0;
  double w = 0.0;
};

}  // namespace strata
