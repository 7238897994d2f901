"""A pytest kit for scripted API tests against a strata robot. In a conftest.py:

    pytest_plugins = ["strata_client.testing"]

Then tests take the fixtures `strata_operator` (a client with the operator token), `strata_viewer` (one
without), `strata_connect` (more clients), `strata_robot` (where the robot is) and `strata_world` (the
simulated world's name, None for a real robot).

By default the kit starts `strata serve` (the binary from STRATA_BINARY or PATH) with the simulator on a free
port, a private maps directory and a fresh operator token, once per test session. To test a running robot
instead, give its address and token: STRATA_URL and STRATA_TOKEN (and STRATA_CA_FILE for a certificate of
your own), or --strata-url / --strata-token / --strata-ca-file.

When proto/ is at hand (STRATA_PROTO_DIR, or the source tree) every message the clients send or receive and
every REST body is checked against its JSON Schema, and a test whose messages break one fails.
"""

from __future__ import annotations

import os
import shlex
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Optional

import pytest

from .client import StrataClient
from .errors import StrataError
from .rest import RestClient
from .schemas import ProtocolChecker, find_proto_dir
from .server import StrataServer, find_strata_binary


@dataclass(frozen=True)
class RobotUnderTest:
    url: str
    token: Optional[str]
    ca_file: Optional[str]
    server: Optional[StrataServer]  # None when attached to a robot started elsewhere

    @property
    def maps_dir(self) -> Optional[Path]:
        """The server's maps directory when the kit started it (a test may look at the files)."""
        return self.server.maps_dir if self.server else None


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("strata", "Strata robot under test")
    group.addoption("--strata-url", default=os.environ.get("STRATA_URL"),
                    help="test the robot at this URL instead of starting one (env STRATA_URL)")
    group.addoption("--strata-token", default=os.environ.get("STRATA_TOKEN"),
                    help="its operator token (env STRATA_TOKEN)")
    group.addoption("--strata-ca-file", default=os.environ.get("STRATA_CA_FILE"),
                    help="CA certificate that signed its TLS certificate (env STRATA_CA_FILE)")
    group.addoption("--strata-binary", default=None, help="strata binary to start (env STRATA_BINARY, or PATH)")
    group.addoption("--strata-world", default=os.environ.get("STRATA_WORLD", "yard"),
                    help="simulated world of the started server (default yard: small and quick)")
    group.addoption("--strata-time-scale", default=os.environ.get("STRATA_TIME_SCALE", "10"),
                    help="simulated seconds per real second of the started server (default 10)")
    group.addoption("--strata-seed", default="1", help="simulator seed of the started server")
    group.addoption("--strata-server-args", default=os.environ.get("STRATA_SERVER_ARGS", ""),
                    help="more `strata serve` arguments for the started server (env STRATA_SERVER_ARGS)")


@pytest.fixture(scope="session")
def strata_robot(request: pytest.FixtureRequest) -> Iterator[RobotUnderTest]:
    """The robot the session tests: attached by URL, or a `strata serve` the kit starts and stops."""
    option = request.config.getoption
    url = option("--strata-url")
    if url:
        yield RobotUnderTest(url, option("--strata-token"), option("--strata-ca-file"), None)
        return
    binary = option("--strata-binary") or find_strata_binary()
    if not binary:
        pytest.fail("no robot to test: set STRATA_BINARY (or put strata on PATH) to start one, or STRATA_URL "
                    "and STRATA_TOKEN to test a running one", pytrace=False)
    args = ["--world", option("--strata-world"), "--time-scale", str(option("--strata-time-scale")),
            "--seed", str(option("--strata-seed")), *shlex.split(option("--strata-server-args"))]
    server = StrataServer(binary, args)
    try:
        yield RobotUnderTest(server.url, server.token, None, server)
    finally:
        server.stop()


@pytest.fixture(scope="session")
def strata_protocol_checker() -> Optional[ProtocolChecker]:
    """Checks messages against proto/schemas/ when proto/ is at hand; None otherwise."""
    proto_dir = find_proto_dir()
    return ProtocolChecker(proto_dir) if proto_dir else None


@pytest.fixture
def strata_connect(strata_robot: RobotUnderTest, strata_protocol_checker: Optional[ProtocolChecker]
                   ) -> Iterator[Callable[..., StrataClient]]:
    """A function that opens a client to the robot: `strata_connect()` with the operator token,
    `strata_connect(token=None)` a viewer. The clients close after the test, and the test fails if any
    message broke its schema."""
    clients: list[StrataClient] = []
    operator_token = strata_robot.token

    def connect(token: Optional[str] = operator_token, **kwargs: object) -> StrataClient:
        client = StrataClient(strata_robot.url, token, ca_file=strata_robot.ca_file, **kwargs)  # type: ignore[arg-type]
        clients.append(client)
        if strata_protocol_checker is not None:
            strata_protocol_checker.watch(client)
        return client

    yield connect
    for client in clients:
        client.close()
    if strata_protocol_checker is not None:
        violations = strata_protocol_checker.take_violations()
        if violations:
            pytest.fail("messages broke proto/'s schemas:\n" + "\n".join(violations[:20]), pytrace=False)


@pytest.fixture
def strata_operator(strata_connect: Callable[..., StrataClient], strata_robot: RobotUnderTest) -> StrataClient:
    """A client with the operator token; it may move the robot."""
    if not strata_robot.token:
        pytest.skip("no operator token for the robot under test (STRATA_TOKEN)")
    client = strata_connect()
    assert client.role == "operator", "the server did not take the operator token"
    return client


@pytest.fixture
def strata_viewer(strata_connect: Callable[..., StrataClient]) -> StrataClient:
    """A client without a token: it may watch only."""
    return strata_connect(token=None)


@pytest.fixture(scope="session")
def strata_world(strata_robot: RobotUnderTest) -> Optional[str]:
    """The simulated world's name ("yard", "campus", ...); None when the robot is not simulated."""
    client = RestClient(strata_robot.url, strata_robot.token, strata_robot.ca_file)
    try:
        return client.get_json("/api/v1/sim/world")["name"]
    except StrataError as error:
        if error.code == "not_found":
            return None
        raise
    finally:
        client.close()
