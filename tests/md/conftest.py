"""Shared fixtures of the MD tests."""

from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).parent / "data" / "compacted_pack_3x3x8.csv"


@pytest.fixture(scope="session")
def compacted_pack():
    """The stored 96-grain quartz pack compacted to 10 MPa (``data/compacted_pack_3x3x8.csv``,
    whose header says how it was made)."""
    import md

    with open(DATA) as fh:
        box = next(line for line in fh if line.startswith("# box_m:")).split(":")[1].split()
    table = np.loadtxt(DATA, delimiter=",")
    z = np.zeros_like(table[:, :3])
    return md.Pack(table[:, :3], z, z.copy(), table[:, 3], md.Box(*map(float, box)), md.QUARTZ,
                   np.zeros((0, 2), np.int32), np.zeros((0, 3)))
