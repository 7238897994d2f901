// The status panel: the robot's pose, whether it can be trusted, how well the last scan registered, the scan
// rate, the map's size and the link's latency (ping round trip, and the age of the newest pose by the
// server's clock).
const degrees = (radians) => (radians * 180) / Math.PI;
const field = (id) => document.getElementById(id);

export class StatusPanel {
  constructor() {
    this.latency = { roundTripMs: null, poseAgeMs: null };
    this.driverFinished = false;
    this.mode = null; // the robot's motion as last shown: 'standing', 'driving', ...
  }

  showPose(pose) {
    field('pose-x').textContent = `${pose.x.toFixed(2)} m`;
    field('pose-y').textContent = `${pose.y.toFixed(2)} m`;
    field('pose-z').textContent = `${pose.z.toFixed(2)} m`;
    field('pose-yaw').textContent = `${degrees(pose.yaw).toFixed(1)}°`;
    field('pose-tilt').textContent = `${degrees(pose.roll).toFixed(1)}° / ${degrees(pose.pitch).toFixed(1)}°`;
    // A replay that has played everything stands, whatever its base could tell.
    const mode = this.driverFinished && pose.mode === 'driving' ? 'standing' : pose.mode;
    field('pose-mode').textContent = mode ?? '–';
    this.mode = mode;
    field('loc-source').textContent = pose.source === 'registration' ? 'scan matching' : 'odometry only';
    if (pose.server_time) this.latency.poseAgeMs = Date.now() - pose.server_time * 1000;
  }

  showStatus(status) {
    // How far the pose can be trusted (ok, degraded, lost) and why, in words: the reason wraps in full.
    const localization = status.localization;
    if (localization) {
      const state = field('loc-state');
      state.textContent = localization.state;
      state.dataset.state = localization.state;
      const reason = field('loc-reason');
      reason.textContent = localization.reason;
      reason.dataset.state = localization.state;
    }
    const r = status.registration;
    // What each scan's registration did: used whole, used except along directions nothing constrains
    // (odometry there), or not used (odometry kept). Fault control's verdicts are not these three.
    field('loc-scans').textContent = `${r.scans}: ${r.full} corrected, ${r.partial} partly, ${r.kept_odometry} kept odometry`;
    const graph = status.pose_graph;
    if (graph) {
      const last =
        graph.last_loop_stamp === null
          ? 'none yet'
          : `at ${graph.last_loop_stamp.toFixed(0)} s, moved ${graph.last_correction_m.toFixed(2)} m`;
      field('loc-loops').textContent = `${graph.loops} over ${graph.keyframes} keyframes · last ${last}`;
      // The IMU's mounting error as the server keeps it between runs: where this run's tilt starts from.
      const kept = graph.imu_calibration;
      if (kept) {
        const tilt = kept.roll_deg === null ? '' : `: ${kept.roll_deg.toFixed(2)}° roll, ${kept.pitch_deg.toFixed(2)}° pitch`;
        const words = {
          off: 'not kept between runs',
          none: 'learning it',
          loaded: `from the last run${tilt}`,
          saved: `kept for the next run${tilt}`,
        };
        const imu = field('loc-imu');
        imu.textContent = words[kept.kept] ?? kept.kept;
        imu.dataset.kept = kept.kept;
      }
    }
    const rate = field('scan-rate');
    // No scans in the rate's window (10 s) is no news while the robot stands: a stop-and-go scanner scans
    // on the move (issue 63: "0.0 / min" read as a fault).
    const perMinute = status.scan_rate * 60;
    if (perMinute >= 0.05) rate.textContent = `${perMinute.toFixed(1)} / min`;
    else rate.textContent = this.mode === 'standing' ? 'standing, no scans' : 'no scans in the last 10 s';
    // The sensor stopped delivering scans it owes (a cable, a crashed lidar): say so until a scan comes.
    const stalled = status.sensor?.state === 'stalled';
    rate.dataset.sensor = stalled ? 'stalled' : 'ok';
    if (stalled) rate.textContent += ` · sensor stalled, ${status.sensor.overdue_seconds.toFixed(0)} s without a scan`;
    if (status.driver) {
      // A replay plays a recording and cannot move; say so, and when it has played everything.
      this.driverFinished = Boolean(status.driver.finished);
      const finished = status.driver.finished ? ' (finished)' : '';
      field('driver').textContent = `${status.driver.kind}${finished}`;
    }
    if (status.map) {
      // Localizing, the map is fixed: it stays as it was saved, and the scans only place the robot in it.
      const mode = field('map-mode');
      mode.textContent = status.map.mode === 'localize' ? 'localizing (fixed)' : 'mapping';
      mode.dataset.mode = status.map.mode;
      const kib = status.map.bytes / 1024;
      const patches = status.map.patches >= 10000 ? `${(status.map.patches / 1000).toFixed(0)}k` : status.map.patches;
      field('map-size').textContent = `${status.map.tiles} tiles · ${patches} patches`;
      field('map-bytes').textContent = kib > 1024 ? `${(kib / 1024).toFixed(1)} MiB` : `${kib.toFixed(0)} KiB`;
    }
    if (!r.last) return;
    const correction = { full: 'corrected', partial: 'partly corrected', none: 'kept odometry' };
    field('loc-last').textContent = correction[r.last.correction] ?? r.last.correction;
    field('loc-fit').textContent = `${(r.last.rmse * 100).toFixed(1)} cm, ${(r.last.seconds * 1000).toFixed(0)} ms`;
    field('loc-message').textContent = r.last.verdict === 'rejected' || r.last.correction === 'partial' ? r.last.message : '';
  }

  showRoundTrip(ms) {
    this.latency.roundTripMs = ms;
    const age = this.latency.poseAgeMs;
    // The pose's age only means something when the two clocks agree (same machine, or NTP): show it
    // when it is plausible.
    const ageText = age !== null && age > -50 && age < 5000 ? ` · pose ${Math.max(age, 0).toFixed(0)} ms old` : '';
    field('latency').textContent = `${ms.toFixed(0)} ms round trip${ageText}`;
  }
}
