#pragma once

#include <memory>
#include <vector>

#include "drivers/scan_event.hpp"
#include "drivers/sim/simulator.hpp"
#include "drivers/sim/world/world_file.hpp"

namespace strata::pipeline::testing {

/// The first three stop-and-go scans of the simulated robot on the campus, taken once per test binary:
/// stepped in-process, no wall clock. Two degrees between beams instead of one: a quarter of the rays,
/// so the tests stay quick under ASan. Each scan carries its true pose.
inline const std::vector<ScanEvent>& campus_scans() {
  static const std::vector<ScanEvent> scans = [] {
    sim::Simulator simulator(std::make_shared<const sim::World>(sim::builtin_world("campus")),
                             {.seed = 5, .tilting = {.slice_step_deg = 2.0, .rotation_step_deg = 2.0}});
    std::vector<ScanEvent> taken;
    while (taken.size() < 3 && simulator.sample().stamp < 600.0) {
      simulator.step(0.02);
      for (ScanEvent& scan : simulator.take_scans())
        taken.push_back(std::move(scan));
    }
    return taken;
  }();
  return scans;
}

}  // namespace strata::pipeline::testing
