#include "drivers/sim/simulator.hpp"

#include <cmath>
#include <utility>

namespace strata::sim {

Simulator::Simulator(std::shared_ptr<const World> world, SimulatorConfig config)
    : world_(std::move(world)),
      config_(config),
      placer_(*world_, config_.geometry),
      base_(config_.limits, world_->description().spawn),
      stance_(placer_.spawn(world_->description().spawn, world_->description().spawn_z)),
      odometry_(config_.limits.wheel_separation, config_.odometry, config_.seed, world_->description().spawn),
      imu_(config_.imu ? std::optional<SimulatedImu>(std::in_place, *config_.imu, config_.seed)
                       : std::nullopt),
      driver_(world_->description().route, config_.cruise_speed),
      tilting_(config_.tilting, config_.seed),
      lidar_(config_.lidar, config_.seed),
      since_last_scan_(config_.scan_spacing) {}  // the first stop-and-go scan is taken at the start

void Simulator::step(double dt) {
  const bool stop_and_go = config_.scanner == ScannerKind::kTilting;
  VelocityCommand command = commanded_ ? command_ : driver_.command(base_.pose());
  // An operator driving by hand is not stopped for the schedule's scan (issue 63: the robot stood 1 s in
  // every 2 m under a held joystick): a scan under way is dropped, and the base scans once they let go.
  const bool by_hand = command.by_hand && (command.v != 0.0 || command.w != 0.0);
  if (stop_and_go && by_hand && tilting_.scanning())
    tilting_.abandon();
  if (stop_and_go && !by_hand && (tilting_.scanning() || since_last_scan_ >= config_.scan_spacing)) {
    command = {};  // stand still to scan (thesis section 3.1)
    const bool stopped = base_.velocity().v == 0.0 && base_.velocity().w == 0.0;
    if (stopped && !tilting_.scanning())
      tilting_.begin(time_);
  }

  const DiffDriveBase::Step next = base_.preview(command, dt);
  const bool standing = next.velocity.v == 0.0 && next.velocity.w == 0.0;
  const auto placed = standing ? TerrainPlacer::Result{true, stance_, {}} : placer_.move(stance_, next.pose);
  if (placed.ok) {
    base_.apply(next);
    // The base moves `distance` across the map; on a slope its wheels roll the longer way along the ground,
    // and that is what encoders count (a real robot's odometry over a 5-degree ramp reads 0.4 % more than
    // the ramp's length on the map).
    const double along_ground = 1.0 / std::cos(0.5 * (stance_.pose.pitch + placed.stance.pose.pitch));
    const WheelTravel rolled{next.wheels.left * along_ground, next.wheels.right * along_ground};
    stance_ = placed.stance;
    // Standing, the base holds its heading (its controller takes no gyro turn while the wheels stand):
    // only a moving base turns, drifting by the gyro's bias left from its calibration at start (the same
    // all run: docs/benchmarks.md, "Ten seeds").
    std::optional<double> gyro_turn;
    if (imu_)
      gyro_turn = standing
                      ? 0.0
                      : imu_->measure_turn(
                            (next.wheels.right - next.wheels.left) / config_.limits.wheel_separation, dt);
    odometry_.integrate(rolled, gyro_turn);
    if (imu_ && standing) {
      standing_turn_ += imu_->measure_standing_turn(dt);
      standing_seconds_ += dt;
    }
    since_last_scan_ += std::abs(next.velocity.v) * dt;
    blocked_by_.clear();
  } else {
    base_.halt();  // a bumper stop: the wheels do not turn, odometry sees nothing
    blocked_by_ = placed.blocked_by;
  }

  if (imu_)
    streamed_gravity_ = imu_->stream_gravity(stance_.pose, standing);

  const Eigen::Isometry3d base_in_world = stance_.pose.to_isometry();
  if (stop_and_go) {
    if (auto scan = tilting_.advance(*world_, base_in_world, time_, time_ + dt); scan && !sensor_out()) {
      since_last_scan_ = 0.0;
      finish_scan(std::move(*scan));
    }
  } else if (config_.scanner == ScannerKind::kLidar) {
    if (auto scan = lidar_.advance(*world_, base_in_world, time_, time_ + dt); scan && !sensor_out())
      finish_scan(std::move(*scan));
  }
  time_ += dt;
}

bool Simulator::sensor_out() const {
  const auto& outage = config_.sensor_outage;
  return outage && time_ >= outage->start && time_ < outage->start + outage->duration;
}

void Simulator::command(const VelocityCommand& command) {
  commanded_ = true;
  command_ = command;
}

void Simulator::finish_scan(ScanEvent scan) {
  scan.odometry = Pose3::from_pose2(odometry_.pose());
  scan.truth = stance_.pose;
  if (imu_) {
    const bool standing = base_.velocity().v == 0.0 && base_.velocity().w == 0.0;
    scan.gravity = imu_->measure_gravity(stance_.pose, standing);
    if (standing_seconds_ > 0.0)
      scan.standing_gyro = StandingGyro{.rate = standing_turn_ / standing_seconds_,
                                        .seconds = standing_seconds_,
                                        .sigma = imu_->gyro_noise_density() / std::sqrt(standing_seconds_)};
    standing_turn_ = standing_seconds_ = 0.0;
  }
  finished_scans_.push_back(std::move(scan));
}

RobotSample Simulator::sample() const {
  RobotSample sample;
  sample.stamp = time_;
  sample.truth = stance_.pose;
  sample.odometry = Pose3::from_pose2(odometry_.pose());
  sample.velocity = base_.velocity();
  sample.velocity_known = true;
  sample.gravity = streamed_gravity_;
  sample.scanning = tilting_.scanning();
  sample.blocked_by = blocked_by_;
  sample.awaiting_scan = config_.scanner == ScannerKind::kLidar ||
                         (config_.scanner == ScannerKind::kTilting && tilting_.scanning());
  return sample;
}

std::vector<ScanEvent> Simulator::take_scans() {
  return std::exchange(finished_scans_, {});
}

}  // namespace strata::sim
