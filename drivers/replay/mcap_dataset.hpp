#pragma once

#include <filesystem>

#include "drivers/replay/dataset.hpp"

namespace strata::replay {

/// An MCAP recording (`strata serve --record-mcap`, mcap_recording_layout.hpp) as a dataset to replay:
/// the whole file is checked first (McapReader: a file cut short or damaged is refused), then its
/// /strata/recording, /strata/scans and /strata/odometry rows are read as the own layout's files are, each
/// scan's points from its /scan message when it is played. Throws DatasetError naming what is wrong.
[[nodiscard]] Dataset open_mcap_recording(const std::filesystem::path& file);

}  // namespace strata::replay
