"""The client against the real server (the kit's `strata serve`, simulated yard): streams, commands, errors.
Every message here is also checked against proto/schemas/ by the kit's fixtures."""

import json
import math
from pathlib import Path

import pytest

from strata_client import (PROTOCOL_MAJOR, ConnectionClosed, GoalReplaced, OccupancyFrame, ProtocolVersionError,
                           StrataClient, StrataError, TileFrame)
from strata_client.connection import check_protocol_version
from strata_client.frames import png_size
from strata_client.schemas import find_proto_dir


def test_hello_says_the_role_and_the_protocol(strata_operator, strata_viewer):
    assert strata_operator.role == "operator"
    assert strata_viewer.role == "viewer"
    assert strata_operator.hello.protocol == "strata.v1"
    info = strata_viewer.rest.info()
    assert (info.name, info.protocol_version) == ("strata", PROTOCOL_MAJOR)
    assert strata_viewer.ping() >= 0


def test_the_client_speaks_the_protocol_version_of_proto():
    hello_schema = json.loads((find_proto_dir() / "schemas/ws-server/hello.schema.json").read_text())
    assert hello_schema["properties"]["protocol_version"]["const"] == PROTOCOL_MAJOR
    assert hello_schema["properties"]["protocol"]["const"] == f"strata.v{PROTOCOL_MAJOR}"


def test_another_major_protocol_version_is_refused():
    check_protocol_version("strata.v1", 1, "hello")
    with pytest.raises(ProtocolVersionError, match="strata.v2"):
        check_protocol_version("strata.v2", 2, "/api/v1/info")
    with pytest.raises(ProtocolVersionError):
        check_protocol_version(None, None, "hello")


def test_a_wrong_token_is_refused_at_the_upgrade(strata_robot):
    with pytest.raises(StrataError) as refused:
        StrataClient(strata_robot.url, "not-the-operator-token-at-all")
    assert refused.value.code == "unauthorized"
    assert refused.value.http_status == 401


def test_bad_input_raises_a_clear_error_before_anything_is_sent(strata_operator):
    robot = strata_operator
    goal_before = robot.rest.goal()
    for x in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValueError, match="finite"):
            robot.set_goal(x, 0.0)
    with pytest.raises(ValueError, match="beyond"):
        robot.set_goal(0.0, 2e6)
    with pytest.raises(TypeError):
        robot.set_goal("far", 0.0)
    with pytest.raises(ValueError):
        robot.teleop(5.0, 0.0)
    with pytest.raises(ValueError):
        robot.teleop(0.0, math.nan)
    for name in ("../etc/passwd", ".hidden", "", "x" * 65):
        with pytest.raises(ValueError, match="map name"):
            robot.maps.save(name)
    with pytest.raises(ValueError):
        robot.maps.download("jpeg")
    with pytest.raises(ValueError):
        robot.subscribe(["poses"])
    with pytest.raises(ValueError, match="token"):
        StrataClient(robot.url, "short")
    assert robot.rest.goal() == goal_before  # and nothing reached the server


def test_the_streams_arrive_typed(strata_viewer):
    robot = strata_viewer
    pose = robot.wait_for_pose()
    assert pose.source in ("odometry", "registration")
    assert pose.truth is not None  # the simulator tells the truth
    status = robot.wait_for("status")
    assert status.driver == "simulator"
    assert status.localization_state in ("ok", "degraded", "lost")
    assert robot.wait_for("goal").phase in ("none", "accepted", "planning", "driving", "reached", "failed",
                                            "cancelled")
    assert robot.wait_for("pose", lambda p: p.stamp > pose.stamp).stamp > pose.stamp


def test_the_map_arrives_as_tile_and_occupancy_frames(strata_viewer):
    robot = strata_viewer
    robot.wait_for_map()
    robot.connection.wait_until(lambda c: c.tiles() and c.occupancy(), timeout=30)
    tiles = robot.tiles
    for tile in tiles.values():
        assert isinstance(tile, TileFrame)
        assert tile.draco.startswith(b"DRACO") and tile.patches > 0
    occupancy = robot.occupancy
    assert isinstance(occupancy, OccupancyFrame)
    assert png_size(occupancy.png) == (occupancy.width, occupancy.height)
    assert occupancy.resolution > 0
    # REST serves the same tiles in the same frame layout, at the version streamed or a newer one.
    index = {(t["x"], t["y"]): t for t in robot.rest.tile_index()["tiles"]}
    some = next(iter(tiles))
    assert some in index
    from_rest = robot.rest.tile(*some)
    assert from_rest.key == some
    assert from_rest.header.version >= tiles[some].header.version
    if from_rest.header.version == tiles[some].header.version:
        assert from_rest.draco == tiles[some].draco
    image = robot.rest.occupancy()
    assert image.png.startswith(b"\x89PNG") and image.resolution > 0


def test_subscribe_picks_the_streams(strata_viewer):
    robot = strata_viewer
    pose_before = robot.wait_for_pose()
    robot.subscribe(["status"])
    ops: list[str] = []
    robot.on("message", lambda message: ops.append(message["op"]))
    # Poses come at 25 Hz, the status at 1 Hz: between two status messages after the subscribe, no pose.
    robot.connection.wait_until(lambda _: ops.count("status") >= 2, timeout=30)
    between = ops[ops.index("status"):]
    assert "pose" not in between, between
    robot.subscribe(["pose", "status"])  # added back: the current pose comes at once
    assert robot.wait_for("pose", lambda p: p.stamp > pose_before.stamp).stamp > pose_before.stamp


def far_goal(robot):
    """Of goals known to be reachable in the yard, the farthest from the robot: it drives for a while."""
    pose = robot.wait_for_pose()
    return max([(-6.0, -5.5), (-6.5, -1.5), (-4.0, -6.0)], key=lambda g: math.hypot(g[0] - pose.x, g[1] - pose.y))


def test_cancel_stops_a_goal(yard_only, strata_operator):
    robot = strata_operator
    robot.stop()
    robot.wait_for_map()
    goal = robot.set_goal(*far_goal(robot))
    assert goal.wait(30, phases=frozenset({"driving", "reached", "failed"})).phase == "driving"
    robot.cancel_goal()
    outcome = goal.wait(30)
    assert (outcome.phase, outcome.reason) == ("cancelled", None)
    robot.wait_until_still()


def test_a_new_goal_replaces_the_one_waited_for(yard_only, strata_operator):
    robot = strata_operator
    robot.stop()
    robot.wait_for_map()
    first = robot.set_goal(*far_goal(robot))
    first.id  # the server has numbered it
    second = robot.set_goal(*far_goal(robot))
    with pytest.raises(GoalReplaced) as replaced:
        first.wait(30)
    assert replaced.value.replaced_by == second.id > first.id
    robot.cancel_goal()


def test_closing_the_operator_connection_cancels_its_goal(yard_only, strata_connect, strata_viewer):
    operator = strata_connect()
    operator.stop()
    operator.wait_for_map()
    goal = operator.set_goal(*far_goal(operator))
    assert goal.wait(30, phases=frozenset({"driving", "reached", "failed"})).phase == "driving"
    operator.close()  # mid-goal
    with pytest.raises(ConnectionClosed):
        goal.wait(1)
    ended = strata_viewer.wait_for("goal", lambda g: g.id == goal.id and g.finished, timeout=30)
    assert (ended.phase, ended.reason) == ("cancelled", "operator_disconnected")


def test_teleop_moves_the_robot_and_the_robot_stops_when_it_ends(strata_operator):
    robot = strata_operator
    robot.stop()
    robot.wait_for_map()
    start = robot.wait_until_still()
    with robot.teleop(0.3, 0.4) as teleop:
        moved = robot.wait_for("pose", lambda p: abs(p.yaw - start.yaw) + math.hypot(p.x - start.x, p.y - start.y)
                               > 0.05, timeout=30)
        assert teleop.active and teleop.failure is None
    assert moved.stamp > start.stamp
    robot.wait_until_still()
    assert robot.errors() == []  # no keep-alive was refused


def test_map_errors_carry_the_protocol_codes(strata_operator, strata_robot):
    robot = strata_operator
    with pytest.raises(StrataError) as missing:
        robot.maps.load("missing.strata")
    assert (missing.value.code, missing.value.http_status) == ("not_found", 404)
    if strata_robot.maps_dir is None:
        pytest.skip("a corrupt map file needs the server's maps directory")
    Path(strata_robot.maps_dir, "corrupt.strata").write_bytes(b"definitely not a map")
    with pytest.raises(StrataError) as corrupt:
        robot.maps.load("corrupt.strata")
    assert corrupt.value.code == "corrupt_file"


def test_the_map_downloads_in_every_format(strata_viewer):
    robot = strata_viewer
    robot.wait_for_map()
    assert robot.maps.download("strata").startswith(b"STRATMLS")
    assert robot.maps.download("ply").startswith(b"ply")
    assert robot.maps.download("pgm").startswith(b"P5")
    assert b"resolution" in robot.maps.download("yaml")


def test_rest_reads_match_the_schemas(strata_viewer):
    robot = strata_viewer
    robot.wait_for_pose()
    assert robot.rest.healthz()
    assert robot.rest.pose().source in ("odometry", "registration")
    assert robot.rest.status().driver == "simulator"
    assert robot.rest.path().length >= 0
    assert "strata_ws_clients" in robot.rest.metrics()
    assert isinstance(robot.maps.list(), list)  # a viewer may list the saved maps
    with pytest.raises(StrataError) as loading:
        robot.maps.load("none.strata")  # but not load one
    assert loading.value.code == "unauthorized"


def test_the_schema_checker_catches_a_message_that_breaks_its_schema(strata_protocol_checker):
    assert strata_protocol_checker is not None, "proto/ not found: set STRATA_PROTO_DIR"
    strata_protocol_checker.on_message("received", {"op": "pose", "x": "north"})
    strata_protocol_checker.on_message("sent", {"op": "set_goal", "x": 1, "y": 1, "speed": 3})
    violations = strata_protocol_checker.take_violations()
    assert any(v.startswith("received pose breaks ws-server/pose") and "'north'" in v for v in violations)
    assert any(v.startswith("sent set_goal breaks ws-client/set_goal") and "'speed'" in v for v in violations)
    assert strata_protocol_checker.checked > 2
