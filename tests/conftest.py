import numpy as np
import pytest


@pytest.fixture
def rng():
    """Seeded random generator: every test that draws numbers is reproducible."""
    return np.random.default_rng(20261122)
