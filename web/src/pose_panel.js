// The pose estimate in the Localization panel: the Set pose button with its press-and-drag tool, and
// what the server's last search for the robot found, in its words. A pose estimate means something only
// in a saved map the robot localizes in; while it maps, the map is wherever its scans put it.
import { PoseTool } from './pose_tool.js';

const $ = (id) => document.getElementById(id);
const round = (value) => Math.round(value * 1000) / 1000;

export class PosePanel {
  /** `command(message)` sends an operator command; `currentYaw()` is the robot's heading now. */
  constructor(view, { command, notices, currentYaw }) {
    this.mapMode = null;
    this.lastSent = null;
    this.lastSearch = null;
    this.searchKey = null;
    this.tool = new PoseTool(view, {
      currentYaw,
      onPose: (pose) => {
        this.lastSent = pose;
        const message = { op: 'set_pose', x: round(pose.x), y: round(pose.y), yaw: round(pose.yaw), z: round(pose.z) };
        if (!command(message)) this.tool.clearMarker();
        else if (!pose.dragged) notices.show('Heading kept from the current estimate: drag from the place to point it', 'info', 5);
      },
      onMiss: () => notices.show('Press on the floor or ground where the robot stands, then drag the way it faces', 'info', 5),
      onArmed: (armed) => {
        $('pose-arm').setAttribute('aria-pressed', String(armed));
        $('pose-arm').textContent = armed ? 'Press and drag…' : 'Set pose';
        $('view').classList.toggle('picking', armed);
      },
    });
    $('pose-arm').addEventListener('click', () => {
      if (!this.tool.armed && this.mapMode === 'mapping') {
        notices.show('The robot is mapping: load a saved map to localize in (Load, "localize") to set its pose in it', 'info', 8);
        return;
      }
      this.tool.setArmed(!this.tool.armed);
    });
  }

  /** The server refused the estimate: the arrow goes, the notice says why. */
  refused() {
    this.tool.clearMarker();
  }

  showStatus(status) {
    this.mapMode = status.map?.mode ?? null;
    const search = status.relocalization ?? null;
    const key = search && `${search.stamp}|${search.message}`;
    if (key === this.searchKey) return;
    this.searchKey = key;
    this.lastSearch = search;
    this.tool.clearMarker();
    const element = $('loc-search');
    element.textContent = search ? search.message : ''; // "found at x 3.10, ...", "no place fits: ..."
    element.dataset.found = search ? String(search.found) : '';
  }
}
