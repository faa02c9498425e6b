"""Output files of the CLI (issue 24, Outputs): one check before the run for every command that
writes — a regular file or a new name in a writable folder, symbolic links written through to
their target — scene names that are plain file names, and writes that SIGINT and SIGTERM
cannot leave half-done (tested in a subprocess)."""

import os
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
import xarray as xr

from rockcem import cli
from rockcem._atomic import atomic_write, output_path
from rockcem._data import data_path
from rockcem.scene import run_scene, scene_from_dict, write_dataset

SMALL = {"name": "s", "lithology": "sandstone",
         "path": {"max_depth": 1000.0, "depth_step": 250.0}, "models": {"hs_gassmann": {}}}
SCENE_TOML = 'name = "s"\nlithology = "sandstone"\n[path]\nmax_depth = 1000.0\n' \
             'depth_step = 250.0\n[models.hs_gassmann]\n'


@pytest.fixture(scope="module")
def scene_nc(tmp_path_factory):
    path = tmp_path_factory.mktemp("scene") / "s.nc"
    write_dataset(run_scene(scene_from_dict(SMALL)), path)
    return path


@pytest.fixture
def no_work(monkeypatch):
    """Make the scene run, the fit and every figure fail loudly: a refusal must come first."""
    import rockcem.scene
    import rockcem.wellfit
    from rockcem import plots

    def ran(*args, **kwargs):
        raise AssertionError("the work started before the output was checked")

    monkeypatch.setattr(rockcem.scene, "run_scene", ran)
    monkeypatch.setattr(rockcem.wellfit, "fit_scene", ran)
    for name in ("depth_trends", "velocity_porosity", "rock_physics_template", "well_overlay",
                 "well_template", "fit_figure", "md_study_velocity"):
        monkeypatch.setattr(plots, name, ran)


def _read_only_folder(folder: Path):
    """Make ``folder`` unwritable for this process (chmod, or as root the immutable flag);
    return the undo, or skip when neither works here."""
    folder.chmod(0o555)
    if not os.access(folder, os.W_OK):
        return lambda: folder.chmod(0o755)
    folder.chmod(0o755)
    if shutil.which("chattr") and subprocess.run(["chattr", "+i", str(folder)],
                                                 capture_output=True, check=False).returncode == 0:
        if not os.access(folder, os.W_OK):
            return lambda: subprocess.run(["chattr", "-i", str(folder)], check=True)
        subprocess.run(["chattr", "-i", str(folder)], check=True)
    pytest.skip("cannot make a read-only folder here")


def _make(kind, folder: Path, name: str):
    """A hostile output of ``kind`` in ``folder``: the option's value, the check that it is left
    as it was, the words of the expected message, and the undo."""
    target = folder / name
    undo = None
    if kind == "fifo":
        os.mkfifo(target)
        left = lambda: stat.S_ISFIFO(os.lstat(target).st_mode)
        words = "is a FIFO, not a regular file"
    elif kind == "device":
        try:
            os.mknod(target, stat.S_IFCHR | 0o666, os.makedev(1, 3))   # a /dev/null
        except PermissionError:
            pytest.skip("cannot make a device node here")
        left = lambda: stat.S_ISCHR(os.lstat(target).st_mode)
        words = "is a character device, not a regular file"
    elif kind == "folder":
        target.mkdir()
        (target / "inside").write_text("keep")
        left = lambda: (target / "inside").read_text() == "keep"
        words = "is a folder"
    elif kind == "under_a_file":
        (folder / "file.txt").write_text("keep")
        target = folder / "file.txt" / name
        left = lambda: (folder / "file.txt").read_text() == "keep"
        words = "file.txt' is a file, not a folder"
    elif kind == "read_only_folder":
        (folder / "ro").mkdir()
        undo = _read_only_folder(folder / "ro")
        target = folder / "ro" / name
        left = lambda: os.listdir(folder / "ro") == []
        words = "ro' is not writable"
    elif kind == "empty":
        target = ""
        left = lambda: True
        words = "empty file name"
    else:                                                             # a folder-like name
        target = f"{folder / 'new'}{os.sep}"
        left = lambda: not (folder / "new").exists()
        words = "ends in a separator"
    return str(target), left, words, undo


KINDS = ["fifo", "device", "folder", "under_a_file", "read_only_folder", "empty", "separator"]


def _commands(tmp_path, scene_nc):
    """Every command that writes, with the option that names each file it writes."""
    las = str(data_path("wells", "synthetic_well.las"))
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE_TOML)
    fit = ["fit", "synthetic_basin_horizons", "--well", las, "--free", "sandstone.beta"]
    return {
        "run -o": (["run", str(scene), "-q", "-o"], "x.nc"),
        "plot -o": (["plot", str(scene_nc), "-o"], "x.png"),
        "plot --kind template -o": (["plot", str(scene_nc), "--kind", "template", "-o"],
                                    "x.png"),
        "plot --well -o": (["plot", str(scene_nc), "--well", las, "-o"], "x.png"),
        "fit -o": (fit + ["-q", "--figure", str(tmp_path / "f.png"), "-o"], "x.toml"),
        "fit --figure": (fit + ["-q", "-o", str(tmp_path / "c.toml"), "--figure"], "x.png"),
        "compare -o": (["compare", str(scene_nc), "--well", las, "-q", "-o"], "x.csv"),
        "compare --figure": (["compare", str(scene_nc), "--well", las, "-q", "--figure"],
                             "x.png"),
    }


@pytest.mark.parametrize("command", ["run -o", "plot -o", "plot --kind template -o",
                                     "plot --well -o", "fit -o", "fit --figure", "compare -o",
                                     "compare --figure"])
@pytest.mark.parametrize("kind", KINDS)
def test_hostile_output_refused_before_the_run_and_left_as_it_was(
        kind, command, tmp_path, scene_nc, no_work, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args, name = _commands(tmp_path, scene_nc)[command]
    (tmp_path / "out").mkdir()
    target, left, words, undo = _make(kind, tmp_path / "out", name)
    before = sorted(os.listdir(tmp_path))
    try:
        assert cli.main(args + [target]) == 2
        err = capsys.readouterr().err
        assert err.startswith("rockcem: error: ") and err.count("\n") == 1, err
        assert words in err and command.split()[-1] in err, err
        assert left()
        assert sorted(os.listdir(tmp_path)) == before        # no calibration, no figure
    finally:
        if undo:
            undo()


def test_empty_output_never_means_the_default(tmp_path, capsys, monkeypatch):
    """``-o ""`` used to write ``<name>.nc``, over an existing file of that name."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SCENE_TOML)
    (tmp_path / "s.nc").write_bytes(b"keep")
    assert cli.main(["run", "s.toml", "-q", "-o", ""]) == 2
    assert "-o: empty file name" in capsys.readouterr().err
    assert (tmp_path / "s.nc").read_bytes() == b"keep"


def test_default_output_in_the_way_is_refused_too(tmp_path, capsys, monkeypatch, no_work):
    """Without -o the scene's ``<name>.nc`` gets the same check (here a FIFO by that name)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SCENE_TOML)
    os.mkfifo(tmp_path / "s.nc")
    assert cli.main(["run", "s.toml", "-q"]) == 2
    assert "output file 's.nc' is a FIFO" in capsys.readouterr().err
    assert stat.S_ISFIFO(os.lstat(tmp_path / "s.nc").st_mode)


def test_symlink_is_written_through_and_kept(tmp_path, scene_nc, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(SCENE_TOML)
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "target.nc").write_bytes(b"old")
    os.symlink(Path("data") / "target.nc", tmp_path / "link.nc")
    os.symlink(Path("data") / "new.nc", tmp_path / "dangling.nc")
    os.symlink(tmp_path / "link.png", tmp_path / "loop.png")        # a loop of two links
    os.symlink(tmp_path / "loop.png", tmp_path / "link.png")
    for link in ("link.nc", "dangling.nc"):
        assert cli.main(["run", "s.toml", "-q", "-o", link]) == 0
        assert (tmp_path / link).is_symlink()
    for written in ("target.nc", "new.nc"):
        back = xr.load_dataset(tmp_path / "data" / written, engine="netcdf4")
        assert back.attrs["scene_name"] == "s" and back.sizes["depth"] == 5
    assert sorted(os.listdir(tmp_path / "data")) == ["new.nc", "target.nc"]   # no .tmp left
    assert cli.main(["plot", str(scene_nc), "-o", "loop.png"]) == 2
    err = capsys.readouterr().err
    assert "-o 'loop.png': too many levels of symbolic links" in err and err.count("\n") == 1
    assert (tmp_path / "loop.png").is_symlink() and (tmp_path / "link.png").is_symlink()


def test_overwrite_keeps_the_file_mode_and_refuses_a_read_only_file(tmp_path):
    path = tmp_path / "x.txt"
    path.write_text("old")
    path.chmod(0o640)
    atomic_write(path, lambda tmp: Path(tmp).write_text("new"))
    assert path.read_text() == "new" and stat.S_IMODE(path.stat().st_mode) == 0o640
    path.chmod(0o444)
    if os.access(path, os.W_OK):
        pytest.skip("root may write a read-only file")
    with pytest.raises(ValueError, match="is read-only"):
        output_path(path)
    with pytest.raises(ValueError, match="is read-only"):
        atomic_write(path, lambda tmp: Path(tmp).write_text("newer"))
    assert path.read_text() == "new"


def test_new_folders_are_made_for_data_but_not_for_figures(tmp_path, scene_nc, capsys):
    assert output_path(tmp_path / "a" / "b" / "x.nc") == tmp_path / "a" / "b" / "x.nc"
    assert not (tmp_path / "a").exists()                        # checking writes nothing
    assert cli.main(["plot", str(scene_nc), "-o", str(tmp_path / "a" / "x.png")]) == 2
    assert f"folder '{tmp_path / 'a'}' does not exist" in capsys.readouterr().err
    write_dataset(xr.Dataset({"v": ("depth", np.zeros(3))}), tmp_path / "a" / "b" / "x.nc")
    assert os.listdir(tmp_path / "a" / "b") == ["x.nc"]


def test_fit_bad_figure_fails_before_anything_is_written(tmp_path, capsys, monkeypatch):
    """``fit --figure x.xyz`` used to exit 2 after it had written the calibration TOML."""
    monkeypatch.chdir(tmp_path)
    las = str(data_path("wells", "synthetic_well.las"))
    args = ["fit", "synthetic_basin_horizons", "--well", las, "--free", "sandstone.beta", "-q"]
    assert cli.main(args + ["--figure", "x.xyz"]) == 2
    err = capsys.readouterr().err
    assert "--figure must end in .png, .pdf, .svg; got 'x.xyz'" in err and err.count("\n") == 1
    assert cli.main(args + ["-o", "same.png", "--figure", "same.png"]) == 2
    assert "-o and --figure name the same file" in capsys.readouterr().err
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("name", ["../../x", "sub/x", "..", ".hidden", "", "   ", "a\\b"])
def test_scene_name_must_be_a_plain_file_name(name, tmp_path, capsys, monkeypatch):
    with pytest.raises(ValueError, match=r"^scene key name must be a plain file name"):
        scene_from_dict(dict(SMALL, name=name))
    work = tmp_path / "a" / "b"                     # "../../x.nc" from here is in tmp_path
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    for text in (SCENE_TOML, '[md]\n'):                        # a scene, and an MD scene
        (work / "bad.toml").write_text(f"name = {name!r}\n" + text.replace('name = "s"\n', ""))
        assert cli.main(["run", str(work / "bad.toml"), "-q"]) == 2
        err = capsys.readouterr().err
        assert "scene key name must be a plain file name" in err and err.count("\n") == 1, err
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a", "b", "bad.toml"]


def test_plain_scene_names_still_run():
    for name in ("my sandstone", "well-12_a", "x.y"):
        assert scene_from_dict(dict(SMALL, name=name)).output == f"{name}.nc"


def test_ctrl_c_becomes_one_line_and_exit_130(monkeypatch, capsys, tmp_path):
    import rockcem.scene

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(rockcem.scene, "run_scene", interrupted)
    (tmp_path / "s.toml").write_text(SCENE_TOML)
    assert cli.main(["run", str(tmp_path / "s.toml"), "-q", "-o", str(tmp_path / "x.nc")]) \
        == 130
    assert capsys.readouterr().err == "rockcem: interrupted\n"


# ------------------------------------------------------------------ signals during the write
def test_handlers_are_restored_and_threads_write_too(tmp_path):
    """The held signals get their own handlers back after a write, a failed one included; off
    the main thread (where Python cannot set handlers) a write still works."""
    import threading

    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    seen = {}

    def write(tmp):
        seen.update({s: signal.getsignal(s) for s in before})
        Path(tmp).write_text("x")

    atomic_write(tmp_path / "a.txt", write)
    assert all(seen[s] is not before[s] for s in before)          # held during the write
    assert {s: signal.getsignal(s) for s in before} == before

    def broken(tmp):
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        atomic_write(tmp_path / "b.txt", broken)
    assert {s: signal.getsignal(s) for s in before} == before
    written = []
    thread = threading.Thread(target=lambda: written.append(
        atomic_write(tmp_path / "c.txt", lambda tmp: Path(tmp).write_text("y"))))
    thread.start()
    thread.join()
    assert written == [tmp_path / "c.txt"] and (tmp_path / "c.txt").read_text() == "y"
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "c.txt"]



#: ``rockcem run`` in a subprocess whose scene run returns a dataset that takes about a second
#: to write (random numbers, zlib level 9).
_WRITER = """
import sys
import numpy as np
import xarray as xr
import rockcem.scene
from rockcem import cli

ds = xr.Dataset({f"v{i}": (("depth",), np.random.default_rng(i).random(600_000))
                 for i in range(3)})
for v in ds.data_vars:
    ds[v].encoding = {"zlib": True, "complevel": 9}
rockcem.scene.run_scene = lambda *args, **kwargs: ds
sys.exit(cli.main(["run", sys.argv[1], "-q", "-o", sys.argv[2]]))
"""


def _interrupt_the_write(tmp_path, signals):
    """Start the writer, send ``signals`` while it writes the data; return the process's exit
    code, its stderr and the folder's listing afterwards."""
    import rockcem

    (tmp_path / "s.toml").write_text(SCENE_TOML)
    (tmp_path / "out.nc").write_bytes(b"previous result")
    root = str(Path(rockcem.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    proc = subprocess.Popen([sys.executable, "-c", _WRITER, "s.toml", "out.nc"], cwd=tmp_path,
                            env=env, stderr=subprocess.PIPE, text=True)
    try:
        # Signal once a megabyte of data is in the temporary file: inside the netCDF writer,
        # where an exception used to deadlock it (every time, in five tries).
        deadline = time.monotonic() + 60
        while not any(p.suffix == ".tmp" and p.stat().st_size > 2**20
                      for p in tmp_path.iterdir()):
            assert proc.poll() is None, proc.stderr.read()
            assert time.monotonic() < deadline, "the write never started"
            time.sleep(0.002)
        for sig in signals:
            proc.send_signal(sig)
            time.sleep(0.05)
        _, err = proc.communicate(timeout=20)          # a deadlock fails here
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, err, sorted(os.listdir(tmp_path))


@pytest.mark.parametrize("sig, code, message", [
    (signal.SIGINT, 130, "rockcem: interrupted\n"),       # Ctrl-C: one line, exit 130
    (signal.SIGTERM, -signal.SIGTERM, ""),                 # timeout, schedulers: ended by it
])
def test_signal_during_the_write_leaves_no_tmp_and_the_old_file(tmp_path, sig, code, message):
    returncode, err, listing = _interrupt_the_write(tmp_path, [sig])
    assert (returncode, err) == (code, message)
    assert listing == ["out.nc", "s.toml"]
    assert (tmp_path / "out.nc").read_bytes() == b"previous result"


def test_second_signal_abandons_the_write_at_once(tmp_path):
    returncode, err, listing = _interrupt_the_write(tmp_path, [signal.SIGTERM, signal.SIGINT])
    assert returncode == 128 + signal.SIGINT and err == ""
    assert listing == ["out.nc", "s.toml"]
    assert (tmp_path / "out.nc").read_bytes() == b"previous result"
