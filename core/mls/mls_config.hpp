#pragma once

namespace strata {

/// How an MLS map turns points into patches (Triebel, Pfaff, Burgard 2006; docs/architecture.md 4.2).
struct MlsConfig {
  double resolution = 0.1;  ///< cell edge, metres
  /// gamma: a point whose vertical gap to every patch of its cell is at least this starts a new patch.
  /// At least the height of the tallest robot that must fit under an overhang (1.0 m in the paper).
  double gap = 1.0;
  /// tau: a point further than this from a horizontal patch's mean turns it into a vertical patch; where
  /// the point and the patch are less certain, one further than three standard deviations of the two, up
  /// to 2 tau.
  double vertical_threshold = 0.1;
  /// Height standard deviation of a point: sigma = sigma_base + sigma_per_metre * range. Grows with range
  /// because the beam's footprint and the angular error grow with it: the sensor's and its pose's, whose
  /// tilt a moving robot knows to about 0.3 degrees (docs/benchmarks.md: a lidar's floor seen at 5-12 m
  /// scattered over 0.13 m).
  double sigma_base = 0.01;
  double sigma_per_metre = 0.005;
  /// Points closer to the sensor than this are dropped: scanners report "no return" as zeros, and the
  /// robot's own body is not map.
  double min_range = 0.1;

  // Dynamic surfaces (thesis 5.3): every hit adds one unit of evidence to a patch (saturating at
  // max_evidence); every sampled ray that passes through it takes one away; at zero it is removed.
  int max_evidence = 8;
  /// Only every n-th point's ray is traced through the map (0 disables free-space clearing). Rays are
  /// what costs; a surface that is really gone is crossed by many rays, so a subsample suffices.
  int free_space_ray_stride = 8;
  /// A ray is traced only up to this horizontal distance short of its end point, so that noisy surfaces
  /// next to the hit (the wall a ray ends on, the floor a grazing ray lands on) are not cleared by it.
  double free_space_stop_short = 0.3;
  /// A horizontal patch is cleared only by rays that end at least this far above or below it: a ray that
  /// grazes a floor and lands on it a little further on did not see through the floor.
  double free_space_height_margin = 0.1;

  // The ground the robot drives over (MlsMap::mark_driven). Not stored in map files: the marks are.
  /// Radius around the robot's ground point marked as driven, metres: the ground under its body, inside
  /// its wheels (small enough for the thesis's wheelchair, on the safe side for a car).
  double driven_radius = 0.3;
  /// A surface within this height of the robot's ground is the one it stands on, metres: localization's
  /// height error plus the floor's noise.
  double driven_tolerance = 0.15;
  /// Two scans' ground points at most this far apart, metres, mark the ground between them driven too: the
  /// robot drove across it. At 5x real time the campus lidar demo mapped one scan in six, 0.5-0.7 m apart,
  /// and a 0.1 m line of cells between two footprints could hold only a face seen from below (the bridge
  /// deck's seam with the plateau): a wall across the way back (issue 58). Farther apart is a jump (a
  /// relocalization, a Set pose), not a drive.
  double driven_stride = 2.0;
};

}  // namespace strata
