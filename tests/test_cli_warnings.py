"""The CLI prints each validity warning once: in the run summary, not again as a Python
warning on stderr (rockcem.RockcemValidityWarning is for callers from Python)."""

import warnings

from rockcem.cli import main


def test_run_prints_each_validity_warning_once(tmp_path, capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # a validity warning escaping main would raise
        assert main(["run", "carcione2022_sandstone", "-o", str(tmp_path / "s.nc")]) == 0
    out, err = capsys.readouterr()
    lines = [line for line in out.splitlines() if line.startswith("warning: ")]
    assert lines and len(lines) == len(set(lines))
    assert "RockcemValidityWarning" not in err and "warning" not in err
