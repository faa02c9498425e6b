"""Issue 22: `rockcem compare` prints every misfit to one precision (four decimals, no
exponent) and depths as given."""

import re

import numpy as np

from rockcem.scene import load_scene, run_scene, write_dataset
from rockcem.synthetic_well import synthetic_well
from rockcem.synthetic_well import write_las


def test_compare_table_has_one_precision(tmp_path, run_cli):
    scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 100.0})
    ds = run_scene(scene)
    write_dataset(ds, tmp_path / "s.nc")
    # a log 1e-5 off the model in density: its bias printed as 0.0000, not 1e-05
    well = synthetic_well(ds, np.arange(500.0, 3000.0, 50.0), sigma={"vp": 0.05,
                          "density": 1e-5}, model="patchy_cement", seed=2)
    write_las(well, tmp_path / "w.las")
    out = run_cli(["compare", "s.nc", "--well", "w.las", "--intervals", "500", "1500",
                   "2950", "-q"], tmp_path)
    assert out.returncode == 0, out.stderr
    rows = [ln for ln in out.stdout.splitlines() if re.match(r"\s*(vp|vs|density)\s", ln)]
    assert rows
    for row in rows:
        fields = row.split()
        assert fields[2] in ("500", "1500") and fields[3] in ("1500", "2950"), row
        for number in fields[5:7]:                      # rms, bias
            assert re.fullmatch(r"-?\d\.\d{4}", number), row
