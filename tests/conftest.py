import numpy as np
import pytest


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
