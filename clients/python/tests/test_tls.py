"""TLS: a server with its own certificate, trusted through the CA file given to the client."""

import shutil
import subprocess

import pytest
import requests

from strata_client import StrataClient
from strata_client.server import StrataServer, find_strata_binary


@pytest.fixture
def tls_server(tmp_path, strata_robot):
    binary = find_strata_binary()
    if strata_robot.server is None or binary is None or shutil.which("openssl") is None:
        pytest.skip("needs the strata binary (the kit starts its own TLS server) and the openssl CLI")
    cert, key = tmp_path / "cert.pem", tmp_path / "key.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
                    "-nodes", "-days", "1", "-subj", "/CN=127.0.0.1", "-addext", "subjectAltName=IP:127.0.0.1",
                    "-keyout", str(key), "-out", str(cert)], check=True, capture_output=True)
    with StrataServer(binary, ["--world", "yard", "--scanner", "none", "--tls-cert", str(cert), "--tls-key", str(key)],
                      work_dir=tmp_path) as server:
        yield server, cert


def test_a_tls_server_is_reached_with_its_ca_file(tls_server, strata_protocol_checker):
    server, cert = tls_server
    assert server.url.startswith("https://")
    with StrataClient(server.url, server.token, ca_file=str(cert)) as robot:
        if strata_protocol_checker is not None:
            strata_protocol_checker.watch(robot)
        assert robot.role == "operator"
        assert robot.wait_for_pose().truth is not None
        assert robot.rest.info().protocol == "strata.v1"
    if strata_protocol_checker is not None:
        assert strata_protocol_checker.take_violations() == []
    # Without the CA file the self-signed certificate is not trusted.
    with pytest.raises(requests.exceptions.SSLError):
        StrataClient(server.url, server.token)
