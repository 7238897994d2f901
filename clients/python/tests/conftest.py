# The client's own tests run from the source tree, installed or not: the package next to them comes first.
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

pytest_plugins = ["strata_client.testing"]


@pytest.fixture
def yard_only(strata_world):
    """The client's tests that drive pick goals in the simulated yard (the kit's default world)."""
    if strata_world != "yard":
        pytest.skip(f"these goals are in the simulated yard, not in {strata_world!r}")
