import numpy as np
import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (no flaky CI); run with
# HYPOTHESIS_PROFILE=explore for fresh random examples.
settings.register_profile("deterministic", derandomize=True, database=None)
settings.register_profile("explore", max_examples=500)
settings.load_profile(__import__("os").environ.get("HYPOTHESIS_PROFILE", "deterministic"))


@pytest.fixture
def rng():
    """Seeded random generator: every test that draws numbers is reproducible."""
    return np.random.default_rng(20261122)


@pytest.fixture
def expect_value_error():
    """Check that ``call()`` raises ValueError naming ``name``, with no warning before it."""
    import warnings

    def check(call, name):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValueError, match=rf"\b{name}\b"):
                call()

    return check


@pytest.fixture
def run_cli():
    """Run ``python -m rockcem.cli ARGS`` in a folder, finding the rockcem under test."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    import rockcem

    root = str(Path(rockcem.__file__).resolve().parents[1])

    def run(args, cwd):
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(
            [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
        return subprocess.run([sys.executable, "-m", "rockcem.cli", *args], capture_output=True,
                              text=True, cwd=cwd, env=env)

    return run
