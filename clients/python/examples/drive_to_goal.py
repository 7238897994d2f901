#!/usr/bin/env python3
"""Drives the robot to a goal and reports how it went.

    STRATA_TOKEN=... python3 drive_to_goal.py http://localhost:8080 -6 -5.5 [z]
"""

import os
import sys

from strata_client import StrataError, connect


def main() -> int:
    if len(sys.argv) not in (4, 5):
        print(__doc__, file=sys.stderr)
        return 2
    url, x, y = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    z = float(sys.argv[4]) if len(sys.argv) == 5 else None
    try:
        with connect(url, token=os.environ.get("STRATA_TOKEN"), ca_file=os.environ.get("STRATA_CA_FILE")) as robot:
            robot.stop()
            robot.wait_for_map()
            outcome = robot.set_goal(x, y, z).wait(timeout=300)
            pose = robot.wait_for_pose()
            print(f"goal {outcome.goal_id}: {outcome.phase} {outcome.reason or ''}; robot at {pose.x:.2f} {pose.y:.2f}")
            return 0 if outcome.reached else 1
    except StrataError as error:
        print(f"refused: {error.code}: {error.message}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
