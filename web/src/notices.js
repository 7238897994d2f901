// Messages for the operator: what the server refused and why, in words, not codes (proto/PROTOCOL.md,
// "Errors"). The newest shows in the message bar until it times out or the next one replaces it.
const EXPLANATIONS = {
  unauthorized: 'needs the operator token (enter it with the Token button)',
  rate_limited: 'too many commands at once; try again in a moment',
  stale_command: 'the link delayed the drive command too long: the robot did not move on it',
  unavailable: 'not available on this server right now',
  not_found: 'not found',
  bad_params: 'the server did not accept the values',
  corrupt_file: 'that map file is damaged; the current map is kept',
  io_error: 'the server could not read or write the file',
  internal: 'the server hit a bug (please report it)',
};

const ACTIONS = {
  set_goal: 'Setting the goal',
  cancel_goal: 'Cancelling the goal',
  teleop: 'Driving',
  save_map: 'Saving the map',
  load_map: 'Loading the map',
  set_pose: 'Setting the pose',
  download: 'Downloading the map',
};

export class Notices {
  constructor(element) {
    this.element = element;
    this.timer = null;
    this.last = null;
  }

  show(text, kind = 'info', seconds = 6) {
    this.last = { text, kind };
    this.element.textContent = text;
    this.element.dataset.kind = kind;
    this.element.hidden = false;
    clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      this.element.hidden = true;
    }, seconds * 1000);
  }

  /** An `error` message from the server, or a REST error body's `error`. */
  serverError({ code, message, request }) {
    const action = ACTIONS[request] ?? 'The request';
    const why = EXPLANATIONS[code] ?? message;
    // The server's own message says more than the generic explanation for these: show both.
    const detail = ['unavailable', 'bad_params', 'not_found'].includes(code) && message ? ` (${message})` : '';
    this.show(`${action} failed: ${why}${detail}`, code === 'unauthorized' ? 'auth' : 'error', 8);
  }
}
