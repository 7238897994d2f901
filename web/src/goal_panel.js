// The Goal panel: the goal's state in words, and the Set goal / Stop buttons with the tap-to-pick tool.
import { GoalTool } from './goal_tool.js';

const $ = (id) => document.getElementById(id);

const phaseText = {
  none: 'no goal',
  accepted: 'goal accepted',
  planning: 'planning a path…',
  driving: 'driving to the goal',
  reached: 'goal reached',
  failed: 'no way to the goal',
  cancelled: 'goal cancelled',
};

const round = (value) => Math.round(value * 1000) / 1000;

export class GoalPanel {
  /** `command(message)` sends an operator command; `notices` says what went wrong. */
  constructor(view, { command, notices }) {
    this.view = view;
    this.lastGoal = { phase: 'none', id: 0 };
    this.lastGoalSent = null;
    this.tool = new GoalTool(view, {
      onPick: (point) => this.send(point),
      onMiss: () => notices.show('Tap a floor or ground surface of the map to set the goal there', 'info', 4),
      onArmed: (armed) => {
        $('goal-arm').setAttribute('aria-pressed', String(armed));
        $('goal-arm').textContent = armed ? 'Tap the map…' : 'Set goal';
        $('view').classList.toggle('picking', armed);
      },
    });
    this.command = command;
    this.nearest = null;
    $('goal-arm').addEventListener('click', () => this.tool.setArmed(!this.tool.armed));
    // A refused goal's nearest place with room, one tap away.
    $('goal-nearest').addEventListener('click', () => {
      if (this.nearest) this.send(this.nearest);
    });
    $('goal-cancel').addEventListener('click', () => {
      this.tool.setArmed(false);
      command({ op: 'cancel_goal' });
    });
  }

  /** Sends set_goal to `point` ({ x, y, z }; without z, the robot's level). */
  send(point) {
    this.lastGoalSent = point;
    const message = { op: 'set_goal', x: round(point.x), y: round(point.y) };
    if (point.z !== undefined) message.z = round(point.z);
    this.command(message);
  }

  /** A goal message from the server. */
  show(goal) {
    this.lastGoal = goal;
    const element = $('goal-state');
    element.dataset.phase = goal.phase;
    let text = phaseText[goal.phase] ?? goal.phase;
    if (goal.x !== undefined && goal.phase !== 'none') text += ` · ${goal.x.toFixed(1)}, ${goal.y.toFixed(1)}`;
    // Why, in the server's words (the same as its log and REST); the code alone from an older server.
    const why = goal.message || goal.reason?.replaceAll('_', ' ');
    if ((goal.phase === 'failed' || goal.phase === 'cancelled') && why) text += `: ${why}`;
    // A goal moved to a place with room says where it went.
    if (goal.phase === 'driving' && goal.message) text += `: ${goal.message}`;
    element.textContent = text;
    this.nearest = goal.phase === 'failed' && goal.nearest ? goal.nearest : null;
    const offer = $('goal-nearest');
    offer.hidden = !this.nearest;
    if (this.nearest) {
      const away = Math.hypot(this.nearest.x - goal.x, this.nearest.y - goal.y);
      offer.textContent = `Go to the nearest place with room, ${away.toFixed(1)} m away`;
    }
    this.view.paths.showGoal(goal);
    this.view.requestRender();
  }
}
