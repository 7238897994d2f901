"""Example API tests to copy for your own robot: each drives the real server through strata_client.

They use the simulated yard (`strata serve --world yard`, the kit's default): a fenced 20 x 20 m yard, the
robot starting at (-7, -6) facing east, a ramp up to a 0.4 m high deck (the platform, x -1..1, y -7..-5)
and down again. Against another world or a real robot, pick your own goals and skip these.
"""

import math

import pytest

from strata_client import StrataClient, StrataError


@pytest.fixture
def yard(strata_world):
    if strata_world != "yard":
        pytest.skip(f"these goals are in the simulated yard; the robot under test is in {strata_world!r}")


def stop_and_wait_for_map(robot: StrataClient) -> None:
    robot.stop()  # the simulator drives a demo route until an operator takes over
    robot.wait_for_map()  # goals need ground the robot has scanned


def test_the_robot_reaches_a_goal_on_the_deck(yard, strata_operator):
    stop_and_wait_for_map(strata_operator)
    # First onto the foot of the ramp: from there the robot's scans see the deck's top.
    assert strata_operator.set_goal(-4.0, -6.0).wait(timeout=60).reached
    goal = strata_operator.set_goal(0.0, -6.0, z=0.4)  # z picks the deck, not the ground beside it
    outcome = goal.wait(timeout=60)
    assert outcome.reached, f"{outcome.phase}: {outcome.reason}"
    pose = strata_operator.wait_for("pose", lambda p: p.stamp >= outcome.state.stamp)
    assert math.hypot(pose.x - 0.0, pose.y + 6.0) < 0.6
    assert pose.truth is not None and pose.truth.z == pytest.approx(0.4, abs=0.05), "on the deck, not beside it"


def test_a_goal_in_a_wall_is_refused_with_the_right_reason(yard, strata_operator):
    stop_and_wait_for_map(strata_operator)
    outcome = strata_operator.set_goal(-9.9, -6.0).wait(timeout=30)  # in the west fence
    assert outcome.phase == "failed"
    assert outcome.reason == "goal_not_drivable"
    assert outcome.message.startswith("the goal is not a drivable place with room for the robot")


def test_a_viewer_cannot_move_the_robot(strata_viewer, strata_operator):
    assert strata_viewer.role == "viewer"
    goal_before = strata_operator.rest.goal()
    attempts = {
        "set_goal": lambda: strata_viewer.set_goal(1.0, 1.0),
        "cancel_goal": strata_viewer.cancel_goal,
        "teleop": lambda: strata_viewer.teleop(0.3, 0.0),
        "rest goal": lambda: strata_viewer.rest.set_goal(1.0, 1.0),
        "save map": lambda: strata_viewer.maps.save("viewer.strata"),
    }
    for what, attempt in attempts.items():
        with pytest.raises(StrataError) as refused:
            attempt()
        assert refused.value.code == "unauthorized", what
    assert strata_operator.rest.goal() == goal_before  # nothing changed


def tile_payloads(robot: StrataClient) -> tuple[int, dict]:
    """The map as the server serves it: its version and every tile's Draco payload, by tile index."""
    index = robot.rest.tile_index()
    return index["version"], {(t["x"], t["y"]): robot.rest.tile(t["x"], t["y"]).draco for t in index["tiles"]}


def test_a_saved_map_reloads_identically(strata_operator):
    robot = strata_operator
    stop_and_wait_for_map(robot)
    # A scan that lands between reading the map and saving it changes it: read again until it holds still.
    for _ in range(10):
        version, saved_tiles = tile_payloads(robot)
        robot.maps.save("reload-test.strata")
        if robot.rest.tile_index()["version"] == version:
            break
    else:
        pytest.fail("the map kept changing while it was saved")
    assert "reload-test.strata" in [m.name for m in robot.maps.list()]

    robot.maps.load("reload-test.strata")
    loaded_version, loaded_tiles = tile_payloads(robot)
    assert loaded_version > version  # a load is a new map version, so every client redraws
    assert loaded_tiles.keys() == saved_tiles.keys()
    assert loaded_tiles == saved_tiles

    with pytest.raises(StrataError) as missing:
        robot.maps.load("no-such-map.strata")
    assert missing.value.code == "not_found"

    # Saved with the pose graph's keyframes, the map can be localized in; then back to mapping.
    assert "localizing" in robot.maps.load("reload-test.strata", mode="localize")
    # Told it stands half a metre and 11 degrees from where it does, the robot is searched for and found
    # where it is (standing still: the latest scan is searched with).
    here = robot.wait_until_still()
    found = robot.set_pose(here.x + 0.4, here.y - 0.3, here.yaw + 0.2)
    assert found.found, found.message
    placed = robot.wait_for("pose", lambda p: p.stamp > here.stamp)
    assert math.hypot(placed.x - here.x, placed.y - here.y) < 0.15, (placed, here)
    assert "mapping" in robot.maps.load("reload-test.strata")
    with pytest.raises(StrataError) as mapping:
        robot.set_pose(here.x, here.y, here.yaw)
    assert mapping.value.code == "bad_params" and "no saved map" in mapping.value.message
    with pytest.raises(ValueError):
        robot.maps.load("reload-test.strata", mode="navigate")
