"""Hostile inputs of issues 24 and 30, run against one or more checkouts of rockcem: one case per
item of issue 24's lists (Outputs; Silent wrong or NaN; Unbounded or unclear) or, with
``--issue 30``, of issue 30's items outside pore fluids and labelled arrays (wells and the CLI;
[models.md] keys; MD stage files and folder; scenes), each classified and judged against what
the issue asks.

Every case runs in a fresh subprocess (``sys.executable``) with ``PYTHONPATH=<tree>``, its own
empty temporary folder as working directory, an address-space limit (``RLIMIT_AS``, 4 GiB by
default) and a timeout (60 s by default, shorter where the case says so; the process group is
killed at the timeout). CLI cases run ``python -m rockcem ...``; Python cases run a short
snippet inside a harness that records the answer, the exception and every warning. Only the
standard library is used here, so the script judges any checkout, old or new.

Each outcome is classified as

* ``refused (ValueError: ...)`` (Python), ``CLI exit 2, one line: ...`` (the CLI's refusal);
* ``answer ...`` or ``exit 0`` with the case's verdict on it (is the answer right; was a file
  destroyed);
* ``traceback <Type>``, ``MemoryError (RLIMIT)``, ``killed by <signal>``, ``timeout after N s``;
* ``warning leaked: ...`` where a RuntimeWarning escaped the call;

and each case has an ``ok`` predicate: what the issue asks (a clear refusal naming the argument
or scene key, or a right answer, and no file destroyed) -> ✓, else ✗.

Run (the results of issue 24 came from the two worktrees; ``--tree`` repeats, ``LABEL=PATH``):

    git worktree add /tmp/rc_before a1123e3~1 --detach
    git worktree add /tmp/rc_after HEAD --detach
    python benchmarks/hostile_inputs.py --tree before=/tmp/rc_before --tree after=/tmp/rc_after \\
        --properties after

writes ``benchmarks/results/hostile_inputs.{md,json}`` (``--out`` to change); the results of
issue 30, ``hostile_inputs_30.{md,json}``, came from

    git worktree add /tmp/rc30_before fe99654 --detach
    python benchmarks/hostile_inputs.py --issue 30 --tree before=/tmp/rc30_before \\
        --tree after=<this checkout>

With no ``--tree``
it judges the checkout it lives in. ``--only ID`` (repeat) runs some cases; ``--list`` lists them.
``--properties LABEL`` also runs the property-based suite (tests/test_boundary_properties.py) in
that tree with ``-s`` and records its counts (functions covered, examples run).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import re
import resource
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import textwrap
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE / "results" / "hostile_inputs"

MEMORY_LIMIT = 4 << 30          # bytes of address space per case
TIMEOUT = 60.0                  # s per case unless the case says otherwise

OUTPUTS = "Outputs"
SILENT = "Silent wrong or NaN"
UNBOUNDED = "Unbounded or unclear"
CLASSES = (OUTPUTS, SILENT, UNBOUNDED)
# Issue 30 (``--issue 30``): the items of its "Why" list outside pore fluids and labelled arrays.
WELLS30 = "Wells and the CLI"
MDKEYS30 = "[models.md] keys"
STAGES30 = "MD stage files and folder"
SCENES30 = "Scenes"
CLASSES30 = (WELLS30, MDKEYS30, STAGES30, SCENES30)


# ------------------------------------------------------------------------------ outcomes
@dataclass
class Outcome:
    """What one run of a case did."""

    kind: str                   # refused raised answer memory timeout killed exit0 cli2 cli2multi
    #                             traceback exit
    msg: str = ""               # the exception's text, or the CLI's stderr line
    exc: str = ""               # exception type
    value: object = None        # a Python case's answer
    warnings: list = field(default_factory=list)
    rc: int | None = None
    wall: float = 0.0
    stdout: str = ""
    stderr: str = ""
    folder: Path | None = None

    @property
    def runtime_warnings(self):
        found = [f"{w['category']}: {w['message']}" for w in self.warnings
                 if w["category"] == "RuntimeWarning"]
        if self.kind in ("exit0", "cli2", "cli2multi", "traceback", "exit"):
            found += [ln[ln.index("RuntimeWarning"):].strip() for ln in self.stderr.splitlines()
                      if "RuntimeWarning" in ln]
        return found

    def text(self) -> str:
        """The classification, one line."""
        k = self.kind
        if k == "refused":
            s = f"refused (ValueError: {_short(self.msg, 140)})"
        elif k == "raised":
            s = f"traceback {self.exc}: {_short(self.msg, 80)}"
        elif k == "answer":
            s = f"answer {_short(_fmt(self.value), 80)}"
        elif k == "memory":
            s = "MemoryError (RLIMIT)"
        elif k == "timeout":
            quiet = not (self.stdout.strip() or self.stderr.strip())
            s = (f"ran with no word, killed at the timeout ({self.wall:.0f} s)" if quiet
                 else f"timeout after {self.wall:.0f} s (killed); printed: "
                      f"{_short(_last_line(self.stdout + self.stderr), 60)}")
        elif k == "killed":
            s = f"killed by {_signame(-self.rc)}"
        elif k == "exit0":
            s = "exit 0"
        elif k == "cli2":
            s = f"CLI exit 2, one line: {_short(self.msg, 140)}"
        elif k == "cli2multi":
            s = f"CLI exit 2, {len(_lines(self.stderr))} lines: {_short(self.msg, 80)}"
        elif k == "traceback":
            s = f"traceback {self.exc}: {_short(self.msg, 80)}"
        else:
            s = f"exit {self.rc}: {_short(self.msg, 80)}"
        if k not in ("timeout",) and self.wall >= 5.0:
            s += f" after {self.wall:.0f} s"
        rw = self.runtime_warnings
        if rw:
            s += f"; warning leaked ({_short(rw[0], 60)})"
        return s


def _lines(text):
    return [ln for ln in text.splitlines() if ln.strip()]


def _last_line(text):
    lines = _lines(text)
    return lines[-1].strip() if lines else ""


def _short(text, n):
    text = " ".join(str(text).split())
    return text if len(text) <= n else text[: n - 1] + "…"


def _signame(num):
    try:
        return signal.Signals(num).name
    except ValueError:
        return f"signal {num}"


def _fmt(value):
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_fmt(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        inner = ", ".join(_fmt(v) for v in value[:6])
        return f"[{inner}{', …' if len(value) > 6 else ''}]"
    return str(value)


# ------------------------------------------------------------------------------ running
HARNESS = '''\
import json, os, sys, time, warnings
_W = []
def _show(message, category, filename, lineno, file=None, line=None):
    if len(_W) < 50:
        _W.append({"category": category.__name__, "message": str(message)[:300],
                   "file": str(filename)})
warnings.showwarning = _show
warnings.simplefilter("always")
def _plain(x):
    try:
        import numpy as np
        if isinstance(x, np.ndarray):
            return _plain(x.tolist())
        if isinstance(x, np.generic):
            return _plain(x.item())
    except ImportError:
        pass
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, complex):
        return repr(x)
    if isinstance(x, (int, float, str, bool)) or x is None:
        return x
    return repr(x)[:500]
def _case():
@BODY@
_t0 = time.perf_counter()
try:
    _out = {"status": "answer", "value": _plain(_case())}
except MemoryError as e:
    _out = {"status": "memory", "msg": str(e)[:300]}
except BaseException as e:
    _out = {"status": "raised", "type": type(e).__name__, "msg": str(e)[:500]}
_out["wall"] = time.perf_counter() - _t0
_out["warnings"] = _W
sys.stdout.write("\\n@@RESULT@@" + json.dumps(_out, default=repr) + "\\n")
sys.stdout.flush()
'''


def _limits(memory):
    def apply():
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def _env(tree, folder):
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PYTHON", "ROCKCEM_")) and k != "MPLBACKEND"}
    env.update(PYTHONPATH=str(tree), ROCKCEM_TREE=str(tree), MPLBACKEND="Agg",
               PYTHONHASHSEED="0", OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               MKL_NUM_THREADS="1", NUMBA_NUM_THREADS="1", HOME=str(folder),
               MPLCONFIGDIR=str(folder / ".mpl"), DASK_TEMPORARY_DIRECTORY=str(folder))
    return env


def run_case(case, tree: Path, memory=MEMORY_LIMIT):
    base = Path(tempfile.mkdtemp(prefix=f"hostile_{case.id}_"))
    try:
        cwd = base
        if case.setup is not None:
            ret = case.setup(base, tree)
            if isinstance(ret, Path) and ret.is_dir():
                cwd = ret
        if case.cli is not None:
            args = case.cli(tree, base) if callable(case.cli) else list(case.cli)
            cmd = [sys.executable, "-m", "rockcem", *args]
        else:
            body = textwrap.indent(textwrap.dedent(case.py).strip() + "\n", "    ")
            (base / "_case.py").write_text(HARNESS.replace("@BODY@", body))
            cmd = [sys.executable, str(base / "_case.py")]
        out = _execute(cmd, cwd, _env(tree, base), case.timeout, memory, case.cli is not None)
        out.folder = base
        for name in ("msg", "stdout", "stderr"):      # the temporary folder's name is noise
            setattr(out, name, getattr(out, name).replace(str(base), "<case folder>"))
        verdict, ok = case.check(out, base)
        return out, verdict, ok
    finally:
        shutil.rmtree(base, ignore_errors=True)


def _execute(cmd, cwd, env, timeout, memory, cli) -> Outcome:
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, errors="replace",
                            preexec_fn=_limits(memory),  # noqa: PLW1509 - only setrlimit
                            start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
        timed_out = True
    wall = time.perf_counter() - t0
    rc = proc.returncode
    if timed_out:
        return Outcome("timeout", rc=rc, wall=wall, stdout=stdout, stderr=stderr)
    if not cli:
        marker = stdout.rfind("@@RESULT@@")
        if marker < 0:
            if rc is not None and rc < 0:
                return Outcome("killed", rc=rc, wall=wall, stdout=stdout, stderr=stderr)
            exc, msg = _exception(stderr)
            kind = "memory" if exc == "MemoryError" else "traceback"
            return Outcome(kind, exc=exc, msg=msg, rc=rc, wall=wall, stdout=stdout,
                           stderr=stderr)
        res = json.loads(stdout[marker + len("@@RESULT@@"):].strip().splitlines()[0])
        common = {"rc": rc, "wall": res["wall"], "stdout": stdout[:marker], "stderr": stderr,
                  "warnings": res["warnings"]}
        if res["status"] == "answer":
            return Outcome("answer", value=res["value"], **common)
        if res["status"] == "memory":
            return Outcome("memory", exc="MemoryError", msg=res["msg"], **common)
        kind = "refused" if res["type"] == "ValueError" else "raised"
        return Outcome(kind, exc=res["type"], msg=res["msg"], **common)
    common = {"rc": rc, "wall": wall, "stdout": stdout, "stderr": stderr}
    if rc < 0:
        return Outcome("killed", **common)
    if "Traceback (most recent call last)" in stderr:
        exc, msg = _exception(stderr)
        return Outcome("memory" if exc == "MemoryError" else "traceback", exc=exc, msg=msg,
                       **common)
    if rc == 0:
        return Outcome("exit0", msg=_last_line(stdout), **common)
    lines = [ln for ln in _lines(stderr) if "Warning" not in ln]
    if rc == 2:
        return Outcome("cli2" if len(_lines(stderr)) == 1 else "cli2multi",
                       msg=lines[0] if lines else "", **common)
    return Outcome("exit", msg=_last_line(stderr), **common)


def _exception(stderr):
    """Type and message of the last exception a traceback printed."""
    for line in reversed(_lines(stderr)):
        m = re.match(r"^([A-Za-z_][\w.]*(?:Error|Exception|Interrupt|Exit|Warning)\w*)"
                     r"(?::\s*(.*))?$", line.strip())
        if m:
            return m.group(1).rsplit(".", 1)[-1], m.group(2) or ""
    return "?", _last_line(stderr)


# ------------------------------------------------------------------------------ cases
@dataclass
class Case:
    id: str
    cls: str
    title: str
    check: Callable                 # (Outcome, folder) -> (verdict text, ok)
    cli: object = None              # list of args, or (tree, folder) -> list
    py: str | None = None           # snippet: the body of a function whose return is the answer
    setup: Callable | None = None   # (folder, tree) -> working folder (default: folder)
    timeout: float = TIMEOUT
    ask: str = ""                   # what the issue asks (the ok predicate in words)


def _names(text, *names):
    return all(n in text for n in names)


def refusal(*names, forbid=()):
    """ok: a Python ValueError (or the CLI's one-line exit 2) naming every one of ``names`` and
    none of ``forbid``."""
    def check(o: Outcome, folder):
        if o.runtime_warnings:
            return "", False
        if o.kind in ("refused", "cli2"):
            named = _names(o.msg, *names)
            bad = [f for f in forbid if f in o.msg]
            if not named:
                return f"does not name {', '.join(names)}", False
            if bad:
                return f"speaks of {', '.join(bad)}", False
            return "", True
        return "", False
    return check


def with_verdict(base, verdict):
    """A check: ``verdict(o, folder) -> (text, ok or None)``; ``None`` defers to ``base``."""
    def check(o, folder):
        text, ok = verdict(o, folder)
        btext, bok = base(o, folder)
        return "; ".join(t for t in (text, btext) if t), (bok if ok is None else ok and bok)
    return check


SMALL = """\
name = "{name}"
lithology = "sandstone"
{top}
[path]
max_depth = {max_depth}
depth_step = {depth_step}
{path}
[models.hs_gassmann]
A = 3.0
{extra}
"""


def scene(folder, file="scene.toml", *, name="small", top="", max_depth="3000.0",
          depth_step="100.0", path="", extra=""):
    text = SMALL.format(name=name, top=top, max_depth=max_depth, depth_step=depth_step,
                        path=path, extra=extra)
    (folder / file).write_text(text)
    return folder / file


def writes_small(folder, tree):
    scene(folder)


def las(tree):
    return str(tree / "datasets" / "wells" / "synthetic_well.las")


OLD = b"OLD CONTENT: must survive\n"


def before_the_run(o, folder):
    """A refusal of an output path is ok only before the run (``run`` prints its summary after
    the run, before it writes)."""
    if "scene small" in o.stdout:
        return "only after the run", False
    return "", None


def both(*verdicts):
    def verdict(o, folder):
        texts, oks = [], []
        for v in verdicts:
            t, ok = v(o, folder)
            if t:
                texts.append(t)
            oks.append(ok)
        ok = None if all(x is None for x in oks) else all(x is not False for x in oks)
        return "; ".join(texts), ok
    return verdict


def tree_run(folder, tree, *args):
    """Run the tree's own rockcem (to make an input file)."""
    subprocess.run([sys.executable, "-m", "rockcem", *args], cwd=folder, env=_env(tree, folder),
                   check=True, capture_output=True, timeout=120)


def _tmp_left(folder):
    return sorted(p.name for p in folder.rglob(".*.tmp"))


def _cases():
    cases = []
    add = cases.append

    # ----------------------------------------------------------------- Outputs
    def fifo_setup(folder, tree):
        scene(folder)
        os.mkfifo(folder / "out.nc")

    def fifo_kept(o, folder):
        st = os.lstat(folder / "out.nc")
        if stat.S_ISFIFO(st.st_mode):
            return "the FIFO is still a FIFO", None
        return "the FIFO was replaced by a regular file", False

    add(Case("o_fifo", OUTPUTS, "`run -o out.nc`, out.nc a FIFO",
             cli=["run", "scene.toml", "-o", "out.nc"], setup=fifo_setup,
             check=with_verdict(refusal("-o", "FIFO"), both(fifo_kept, before_the_run)),
             timeout=30,
             ask="exit 2 naming -o and the FIFO, which stays a FIFO"))

    def dev_setup(folder, tree):
        scene(folder)
        try:
            os.mknod(folder / "out.nc", stat.S_IFCHR | 0o666, os.makedev(1, 3))
        except OSError as exc:
            raise Skip(f"mknod not permitted here ({exc.strerror})")

    def dev_kept(o, folder):
        st = os.lstat(folder / "out.nc")
        if stat.S_ISCHR(st.st_mode):
            return "the device node is still a device node", None
        return "the device node was replaced by a regular file", False

    add(Case("o_device", OUTPUTS,
             "`run -o out.nc`, out.nc a character device (a null device made with mknod in "
             "the case's folder; never /dev/full)",
             cli=["run", "scene.toml", "-o", "out.nc"], setup=dev_setup,
             check=with_verdict(refusal("-o", "device"), both(dev_kept, before_the_run)),
             timeout=30,
             ask="exit 2 naming -o and the device, which stays a device node"))

    def fifo_named(name):
        def verdict(o, folder):
            if stat.S_ISFIFO(os.lstat(folder / name).st_mode):
                return "the FIFO is still a FIFO", None
            return "the FIFO was replaced by a regular file", False
        return verdict

    def plot_setup(folder, tree):
        scene(folder)
        tree_run(folder, tree, "run", "scene.toml", "-o", "small.nc", "-q")
        os.mkfifo(folder / "fig.png")

    add(Case("o_fifo_plot", OUTPUTS, "`plot small.nc -o fig.png`, fig.png a FIFO",
             cli=["plot", "small.nc", "-o", "fig.png"], setup=plot_setup,
             check=with_verdict(refusal("-o", "FIFO"), fifo_named("fig.png")), timeout=30,
             ask="exit 2 naming -o and the FIFO, which stays a FIFO"))

    def fit_fifo_setup(folder, tree):
        os.mkfifo(folder / "cal.toml")

    add(Case("o_fifo_fit", OUTPUTS,
             "`fit synthetic_basin_horizons ... -o cal.toml`, cal.toml a FIFO",
             cli=lambda tree, folder: ["fit", "synthetic_basin_horizons", "--well", las(tree),
                                       "--free", "models.patchy_cement.coordination_number",
                                       "--model", "patchy_cement", "--figure", "fit.png",
                                       "-o", "cal.toml", "-q"], setup=fit_fifo_setup,
             check=with_verdict(refusal("-o", "FIFO"), fifo_named("cal.toml")), timeout=60,
             ask="exit 2 naming -o and the FIFO, before the fit; the FIFO stays a FIFO"))

    def empty_o_setup(folder, tree):
        scene(folder)
        (folder / "small.nc").write_bytes(OLD)

    def old_kept(name):
        def verdict(o, folder):
            p = folder / name
            if p.is_file() and p.read_bytes() == OLD:
                return f"the existing {name} is untouched", None
            return f"the existing {name} was overwritten", False
        return verdict

    add(Case("o_empty", OUTPUTS, '`run -o ""` with an existing small.nc (the scene\'s name)',
             cli=["run", "scene.toml", "-o", ""], setup=empty_o_setup,
             check=with_verdict(refusal("-o", "empty"),
                               both(old_kept("small.nc"), before_the_run)),
             ask="exit 2 naming -o; small.nc untouched"))

    def link_setup(folder, tree):
        scene(folder)
        (folder / "target.nc").write_bytes(OLD)
        os.symlink("target.nc", folder / "link.nc")

    def link_verdict(o, folder):
        link, target = folder / "link.nc", folder / "target.nc"
        is_link = os.path.islink(link)
        t_new = target.is_file() and target.read_bytes()[:4] in (b"\x89HDF", b"CDF\x01")
        t_old = target.is_file() and target.read_bytes() == OLD
        if o.kind != "exit0":
            return f"not written (link {'kept' if is_link else 'gone'})", False
        if is_link and t_new:
            return "written through: the link is kept, its target holds the new file", True
        if not is_link and t_old:
            return "the link was replaced by a regular file; its target untouched", False
        return (f"link {'kept' if is_link else 'replaced'}, target "
                f"{'new' if t_new else 'old' if t_old else 'gone'}"), False

    add(Case("o_symlink", OUTPUTS, "`run -o link.nc`, link.nc a symlink to target.nc",
             cli=["run", "scene.toml", "-o", "link.nc"], setup=link_setup,
             check=link_verdict,
             ask="one documented way (HEAD's: write through to the target, keep the link); "
                 "ok where the link survives"))

    def dir_setup(folder, tree):
        scene(folder)
        (folder / "out.nc").mkdir()

    add(Case("o_dir", OUTPUTS, "`run -o out.nc`, out.nc an existing folder",
             cli=["run", "scene.toml", "-o", "out.nc"], setup=dir_setup,
             check=with_verdict(refusal("-o", "folder"), before_the_run),
             ask="exit 2 naming -o, before the run"))

    def under_file_setup(folder, tree):
        scene(folder)
        (folder / "file.txt").write_text("a file\n")

    add(Case("o_under_file", OUTPUTS, "`run -o file.txt/out.nc` (a path under a file)",
             cli=["run", "scene.toml", "-o", "file.txt/out.nc"], setup=under_file_setup,
             check=with_verdict(refusal("-o", "file"), before_the_run),
             ask="exit 2 naming -o, before the run"))

    def dotdot_setup(folder, tree):
        work = folder / "a" / "b"
        work.mkdir(parents=True)
        scene(work, name="../../x")
        return work

    def nothing_outside(o, folder):
        outside = [p.relative_to(folder).as_posix() for p in folder.glob("*.nc")]
        outside += [p.relative_to(folder).as_posix() for p in (folder / "a").glob("*.nc")]
        if outside:
            return f"wrote outside the working folder: {', '.join(outside)}", False
        return "nothing written outside the working folder", None

    add(Case("o_name_dotdot", OUTPUTS, 'scene `name = "../../x"`, `run` without -o',
             cli=["run", "scene.toml"], setup=dotdot_setup,
             check=with_verdict(refusal("name"), nothing_outside),
             ask="exit 2 naming the key name; nothing written outside"))

    def empty_name_setup(folder, tree):
        scene(folder, name="")

    def no_hidden(o, folder):
        if (folder / ".nc").exists():
            return "wrote a hidden .nc", False
        return "", None

    add(Case("o_name_empty", OUTPUTS, 'scene `name = ""`, `run` without -o',
             cli=["run", "scene.toml"], setup=empty_name_setup,
             check=with_verdict(refusal("name"), no_hidden),
             ask="exit 2 naming the key name; no hidden .nc"))

    signal_snippet = """
        import glob, os, signal, threading, time
        import numpy as np, xarray as xr
        from rockcem.scene import write_dataset
        ds = xr.Dataset({{"x": ("i", np.random.default_rng(0).random(6_000_000))}})
        ds["x"].encoding = {{"zlib": True, "complevel": 9, "shuffle": False}}
        def send():
            while not glob.glob(".out.nc.*.tmp"):
                time.sleep(0.001)
            time.sleep(0.3)
            print("sent", flush=True)
            os.kill(os.getpid(), signal.{sig})
        threading.Thread(target=send, daemon=True).start()
        write_dataset(ds, "out.nc")
        return "the write returned"
    """

    def signal_setup(folder, tree):
        (folder / "out.nc").write_bytes(OLD)

    def signal_verdict(o, folder):
        left = _tmp_left(folder)
        target = folder / "out.nc"
        data = target.read_bytes() if target.is_file() else b""
        state = ("out.nc untouched" if data == OLD else
                 "out.nc replaced by the complete new file" if data[:4] == b"\x89HDF" else
                 "out.nc damaged or gone")
        parts = [f"temporary file left: {', '.join(left)}" if left else "no temporary file left",
                 state]
        ok = not left and "damaged" not in state and o.kind != "timeout"
        return "; ".join(parts), ok

    add(Case("o_sigterm", OUTPUTS,
             "SIGTERM while `write_dataset` (what `run` writes with) writes out.nc (a 48 MB "
             "zlib-9 Dataset; a thread sends the signal 0.3 s after the temporary file appears)",
             py=signal_snippet.format(sig="SIGTERM"), setup=signal_setup, check=signal_verdict,
             timeout=60, ask="no temporary file left, out.nc untouched (or whole), no hang"))
    add(Case("o_sigint_lock", OUTPUTS,
             "SIGINT (Ctrl-C) while `write_dataset` writes out.nc and xarray holds its file "
             "lock: forced, the signal is sent from inside the middle lock acquisition of the "
             "write (counted on a first write of the same Dataset), the moment that deadlocked "
             "4 of 5 Ctrl-Cs in the issue (20-s timeout)",
             py="""
                import os, signal
                import numpy as np, xarray as xr
                import xarray.backends.locks as locks
                from rockcem.scene import write_dataset
                ds = xr.Dataset({f"v{i}": ("depth", np.arange(1000.0) + i) for i in range(20)})
                original, count, shoot = locks.acquire, [0], [None]
                def acquire(lock, blocking=True):
                    got = original(lock, blocking)
                    count[0] += 1
                    if count[0] == shoot[0]:
                        os.kill(os.getpid(), signal.SIGINT)
                    return got
                locks.acquire = acquire
                ds.to_netcdf("dry.nc", engine="netcdf4")
                os.unlink("dry.nc")
                shoot[0], count[0] = count[0] // 2, 0
                write_dataset(ds, "out.nc")
                return "the write returned"
             """, setup=signal_setup, check=signal_verdict, timeout=20,
             ask="no deadlock, no temporary file left, out.nc untouched (or whole)"))

    def fit_verdict(o, folder):
        written = sorted(p.name for p in folder.glob("*.toml") if p.name != "scene.toml")
        if written:
            return f"wrote {', '.join(written)} first", False
        return "nothing written", None

    add(Case("o_fit_figure", OUTPUTS,
             "`fit synthetic_basin_horizons --figure x.xyz -o cal.toml` (a figure suffix "
             "that cannot be written)",
             cli=lambda tree, folder: ["fit", "synthetic_basin_horizons", "--well", las(tree),
                                       "--free", "models.patchy_cement.coordination_number",
                                       "--model", "patchy_cement", "--figure", "x.xyz",
                                       "-o", "cal.toml", "-q"],
             check=with_verdict(refusal("x.xyz"), fit_verdict),
             ask="exit 2 naming the figure before anything is written"))

    # ----------------------------------------------------------------- Silent wrong or NaN
    def between(key, lo_hi):
        def check(o, folder):
            if o.kind == "answer":
                v = o.value
                lo, hi = sorted(v[lo_hi])
                inside = lo - 1e-9 <= v[key] <= hi + 1e-9
                return (f"{'within' if inside else 'outside'} the single-mineral answers "
                        f"[{lo:.3g}, {hi:.3g}]"), inside and not o.runtime_warnings
            return refusal("solid_fractions")(o, folder)
        return check

    add(Case("s_gg", SILENT, "`fluids.generalized_gassmann(10, [36.6, 76.8], [1.0], 2.25, 0.2)`",
             py="""
                from rockcem import fluids
                single = [float(fluids.gassmann(10.0, k, 2.25, 0.2)) for k in (36.6, 76.8)]
                K = fluids.generalized_gassmann(10, [36.6, 76.8], [1.0], 2.25, 0.2)
                return {"K_G": float(K), "single": single}
             """, check=between("K_G", "single"),
             ask="refused naming solid_fractions, or an answer between the two minerals' own"))
    add(Case("s_gg_dry", SILENT,
             "`fluids.generalized_gassmann_dry(15, [36.6, 76.8], [1.0], 2.25, 0.2)`",
             py="""
                from rockcem import fluids
                single = [float(fluids.gassmann_dry(15.0, k, 2.25, 0.2)) for k in (36.6, 76.8)]
                K = fluids.generalized_gassmann_dry(15, [36.6, 76.8], [1.0], 2.25, 0.2)
                return {"K_m": float(K), "single": single}
             """, check=with_verdict(refusal("solid_fractions"), lambda o, f: (
                 "accepted one fraction for two solids", False)
                 if o.kind == "answer" else ("", None)),
             ask="refused naming solid_fractions (one fraction for two solids has no answer)"))
    add(Case("s_density_phi", SILENT,
             "`models.bulk_density([2.65], [1.0], 1.2, 1.0)` (porosity 1.2)",
             py="""
                from rockcem import models
                return float(models.bulk_density([2.65], [1.0], 1.2, 1.0))
             """, check=refusal("porosity"), ask="refused naming porosity"))
    add(Case("s_density_neg", SILENT,
             "`models.bulk_density([-2.65], [1.0], 0.2, 1.0)` (negative density)",
             py="""
                from rockcem import models
                return float(models.bulk_density([-2.65], [1.0], 0.2, 1.0))
             """, check=refusal("mineral_density"), ask="refused naming mineral_density"))

    def kelvin_setup(folder, tree):
        scene(folder, depth_step="10.0", path="surface_temperature = 288.15")

    def kelvin_verdict(o, folder):
        out = folder / "out.nc"
        if o.kind == "exit0" and out.exists():
            try:
                import xarray as xr
                with xr.open_dataset(out) as ds:
                    c = ds["cement_fraction"].sel(depth=10.0).item()
                    T = ds["temperature"].sel(depth=10.0).item() if "temperature" in ds else None
                extra = f", {T:.0f} degC" if T is not None else ""
                return f"ran: cement fraction {c:.3f} at 10 m{extra}", False
            except Exception as exc:                # noqa: BLE001 - only a description
                return f"ran ({type(exc).__name__} reading the output)", False
        return "", None

    add(Case("s_kelvin_scene", SILENT, "scene `surface_temperature = 288.15` (kelvin), `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"], setup=kelvin_setup,
             check=with_verdict(refusal("surface_temperature"), kelvin_verdict),
             ask="exit 2 naming surface_temperature"))
    add(Case("s_kelvin_linear", SILENT, "`burial.linear_path(30, 40, 288.15, 5000)`",
             py="""
                import burial
                p = burial.linear_path(30, 40, 288.15, 5000)
                return {"nodes": int(p.depth.size), "T(0)": float(p.temperature[0])}
             """, check=refusal("surface_temperature"), ask="refused naming surface_temperature"))
    add(Case("s_start_nan", SILENT,
             "`burial.quartz_cement(linear_path(30, 40, 15, 4000, depth_step=1000), 0.36, 0.3, "
             "0.65, start_temperature=nan)`",
             py="""
                import burial
                p = burial.linear_path(30, 40, 15, 4000, depth_step=1000)
                return burial.quartz_cement(p, 0.36, 0.3, 0.65, start_temperature=float("nan"))
             """, check=refusal("start_temperature"), ask="refused naming start_temperature"))
    for label, value in (("nan", "nan"), ("inf", "inf")):
        add(Case(f"s_offset_{label}", SILENT,
                 f"`rockcem.wells.read_well(synthetic_well.las, depth_offset={value})`",
                 py=f"""
                    import os
                    from rockcem.wells import read_well
                    w = read_well(os.path.join(os.environ["ROCKCEM_TREE"], "datasets", "wells",
                                               "synthetic_well.las"),
                                  depth_offset=float("{value}"))
                    d = w["depth"].values
                    return {{"depth": [float(d.min()), float(d.max())]}}
                 """, check=refusal("depth_offset"), ask="refused naming depth_offset"))
    def nan_table(o, folder):
        if o.kind == "exit0":
            return ("printed a table with NaN" if "nan" in o.stdout.lower()
                    else "printed a table"), False
        return "", None

    add(Case("s_compare_offset", SILENT,
             "`compare carcione2022_sandstone --well synthetic_well.las --depth-offset nan`",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well", las(tree),
                                       "--depth-offset", "nan"],
             check=with_verdict(refusal("depth_offset"), nan_table),
             ask="exit 2 naming depth_offset"))

    add(Case("s_intervals_nan", SILENT,
             "`compare carcione2022_sandstone --well synthetic_well.las --intervals nan 1000`",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well", las(tree),
                                       "--intervals", "nan", "1000"],
             check=with_verdict(refusal("intervals"), nan_table),
             ask="exit 2 naming intervals"))

    def ran_verdict(o, folder):
        if o.kind == "exit0":
            return "ran (one key ignored)", False
        return "", None

    add(Case("s_heating_and_rate", SILENT,
             "scene with both `heating_rate = 2.0` and `sedimentation_rate = 40.0`, `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=lambda folder, tree: scene(
                 folder, path="sedimentation_rate = 40.0\nheating_rate = 2.0"),
             check=with_verdict(refusal("heating_rate", "sedimentation_rate"), ran_verdict),
             ask="exit 2 naming both keys"))

    def horizons_setup(folder, tree):
        (folder / "history.csv").write_text(
            "horizon,age (Ma),depth (m),temperature (degC),time (Ma)\n"
            "A,20,0,15,40\nA,10,1000,45,20\nA,0,2000,75,0\n"
            "B,10,0,15,20\nB,0,1000,45,0\n")
        (folder / "scene.toml").write_text(
            'name = "small"\nlithology = "sandstone"\n[path]\nkind = "horizons"\n'
            'table = "history.csv"\n[models.hs_gassmann]\nA = 3.0\n')

    add(Case("s_horizons_age_time", SILENT,
             "horizons CSV with both an `age (Ma)` and a `time (Ma)` column (different values), "
             "`run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"], setup=horizons_setup,
             check=with_verdict(refusal("age", "time"),
                                lambda o, f: ("ran with one of the columns", False)
                                if o.kind == "exit0" else ("", None)),
             ask="exit 2 naming both columns"))
    add(Case("s_path_negative", SILENT,
             "`burial.BurialPath([0, 1], [-5, -3], [15, 20])` (negative depths)",
             py="""
                import burial
                return repr(burial.BurialPath([0.0, 1.0], [-5.0, -3.0], [15.0, 20.0]))
             """, check=refusal("depth"), ask="refused naming depth"))
    add(Case("s_path_complex", SILENT,
             "`burial.quartz_cement(BurialPath([0, 1], [0, 3+1j], [15, 20]), 0.36, 0.3, 0.65)` "
             "(a complex depth)",
             py="""
                import burial
                p = burial.BurialPath([0.0, 1.0], [0.0, 3.0 + 1j], [15.0, 20.0])
                return burial.quartz_cement(p, 0.36, 0.3, 0.65)
             """, check=refusal("depth"), ask="refused naming depth"))

    def empty_file(o, folder):
        out = folder / "out.nc"
        if o.kind == "exit0" and out.exists():
            try:
                import xarray as xr
                with xr.open_dataset(out) as ds:
                    return f"wrote a file with {len(ds.data_vars)} variables", False
            except Exception as exc:                # noqa: BLE001
                return f"wrote out.nc ({type(exc).__name__} reading it)", False
        return "", None

    add(Case("s_outputs_empty", SILENT, "scene `outputs = []`, `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=lambda folder, tree: scene(folder, top="outputs = []"),
             check=with_verdict(refusal("outputs"), empty_file), ask="exit 2 naming outputs"))
    add(Case("s_coordination_text", SILENT,
             '`models.patchy_cement_model(quartz, quartz_cement, 0.25, 0.05, 20, water, '
             'coordination_number="9")`',
             py="""
                from rockcem import models
                from rockcem.materials import fluid, mineral
                r = models.patchy_cement_model(mineral("quartz"), mineral("quartz_cement"), 0.25,
                                               0.05, 20.0, fluid("water"),
                                               coordination_number="9")
                return {"vp": float(r.vp)}
             """, check=refusal("coordination_number"), ask="refused naming coordination_number"))

    # ----------------------------------------------------------------- Unbounded or unclear
    add(Case("u_depth_step", UNBOUNDED, "scene `depth_step = 1e-6`, `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=lambda folder, tree: scene(folder, depth_step="1e-6"),
             check=refusal("depth_step"), ask="exit 2 naming depth_step, no allocation"))
    add(Case("u_max_depth", UNBOUNDED, "scene `max_depth = 1e300`, `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=lambda folder, tree: scene(folder, max_depth="1e300"),
             check=refusal("max_depth"), ask="exit 2 naming max_depth, no allocation"))
    add(Case("u_linear_1e8", UNBOUNDED, "`burial.linear_path(30, 40, 15, 1e8)` (to 1e8 m)",
             py="""
                import burial
                return {"nodes": int(burial.linear_path(30, 40, 15, 1e8).depth.size)}
             """, check=refusal("max_depth"), ask="refused naming max_depth"))
    add(Case("u_settle", UNBOUNDED, "`md.settle((1e4,)*3)`",
             py="""
                import md
                pack = md.settle((1e4,) * 3)
                return {"grains": int(pack.radii.size)}
             """, check=refusal("size"), timeout=60, ask="refused naming size"))

    def sweep_setup(n, per_axis):
        def setup(folder, tree):
            g = ", ".join(f"{20.0 + 20.0 * i / max(per_axis - 1, 1):.6f}" for i in range(per_axis))
            b = ", ".join(f"{0.005 + 0.015 * i / max(per_axis - 1, 1):.8f}"
                          for i in range(per_axis))
            scene(folder, max_depth="1000.0", depth_step="500.0",
                  extra=f'[sweep]\n"path.gradient" = [{g}]\n"sandstone.beta" = [{b}]\n')
        return setup

    add(Case("u_sweep_1e6", UNBOUNDED,
             "sweep of 10^6 members (1000 gradients x 1000 betas), `run` (20-s timeout)",
             cli=["run", "scene.toml", "-o", "out.nc"], setup=sweep_setup(10**6, 1000),
             check=refusal("members"), timeout=20,
             ask="exit 2 naming the bound (members, --max-members) before any work"))

    add(Case("u_load_pack", UNBOUNDED, "`md.load_pack` on a pack file cut to half its length",
             py="""
                import numpy as np
                from md.contact import QUARTZ
                from md.space import Box
                from md.state import Pack, load_pack, save_pack
                rng = np.random.default_rng(0)
                n, m = 2000, 700
                pack = Pack(positions=rng.uniform(0, 1e-3, (n, 3)),
                            velocities=rng.normal(size=(n, 3)),
                            angular_velocities=rng.normal(size=(n, 3)),
                            radii=rng.uniform(1.8e-4, 2e-4, n), box=Box(2e-3, 2e-3, 0.0, 5e-3),
                            material=QUARTZ, pairs=rng.integers(0, n, (m, 2)).astype(np.int32),
                            history=rng.normal(size=(m, 3)), stage="settle", time=1.0,
                            metadata={"seed": 7})
                save_pack(pack, "pack.nc")
                data = open("pack.nc", "rb").read()
                open("pack.nc", "wb").write(data[: len(data) // 2])
                back = load_pack("pack.nc")
                return {"grains": int(back.radii.size)}
             """, check=refusal("pack.nc"), ask="ValueError naming the file"))

    def fast(limit):
        def verdict(o, folder):
            if o.wall > limit:
                return f"only after {o.wall:.0f} s", False
            return "", None
        return verdict

    add(Case("u_scheduler_cli", UNBOUNDED,
             "`run sweep.toml --scheduler tcp://127.0.0.1:1` (nothing listens; 2-member sweep)",
             cli=["run", "scene.toml", "-o", "out.nc", "-q", "--scheduler",
                  "tcp://127.0.0.1:1"], setup=sweep_setup(4, 2),
             check=with_verdict(refusal("127.0.0.1:1"), fast(15.0)),
             ask="exit 2, one line naming the address, within seconds"))
    add(Case("u_scheduler_py", UNBOUNDED,
             '`run_scene(load_scene(sweep), scheduler="tcp://127.0.0.1:1")` from Python',
             py="""
                from rockcem.scene import load_scene, run_scene
                ds = run_scene(load_scene("scene.toml"), scheduler="tcp://127.0.0.1:1")
                return {"members": int(ds.sizes.get("gradient", 0))}
             """, setup=sweep_setup(4, 2),
             check=with_verdict(refusal("scheduler"), fast(15.0)),
             ask="ValueError naming scheduler, within seconds"))
    add(Case("u_msg_internal", UNBOUNDED,
             "`granular.soft_sand(36.6, 45, [0.2, 0.25, 0.3], 0.4, [9, 8], 10)` (phi and n "
             "of different lengths)",
             py="""
                from rockcem import granular
                return granular.soft_sand(36.6, 45.0, [0.2, 0.25, 0.3], 0.4, [9.0, 8.0], 10.0)
             """, check=refusal("phi", "n", forbid=("K_a", "frac_a", "K_ref", "G_ref",
                                                    "operands")),
             ask="refused naming phi and n, no internal array names"))
    add(Case("u_msg_broadcast", UNBOUNDED,
             "`models.bulk_density([2.65, 2.7], [[0.9, 0.1]]*3, [0.2, 0.3], 1.0)` (shapes)",
             py="""
                from rockcem import models
                return models.bulk_density([2.65, 2.7], [[0.9, 0.1]] * 3, [0.2, 0.3], 1.0)
             """, check=with_verdict(
                 refusal("solid_fractions", "porosity", forbid=("operands",)),
                 lambda o, f: ("porosity shown as (2, 1), not the (2,) passed", None)
                 if "porosity (2, 1)" in o.msg else ("", None)),
             ask="refused naming the arguments, not numpy's broadcast text"))
    add(Case("u_msg_n", UNBOUNDED,
             "`models.patchy_cement_model(..., coordination_number=-1)`",
             py="""
                from rockcem import models
                from rockcem.materials import fluid, mineral
                r = models.patchy_cement_model(mineral("quartz"), mineral("quartz_cement"), 0.25,
                                               0.05, 20.0, fluid("water"),
                                               coordination_number=-1.0)
                return {"vp": float(r.vp)}
             """, check=refusal("coordination_number"),
             ask="refused naming coordination_number (the scene key), not n"))

    def finite_silent(o, folder):
        if o.kind == "answer":
            vals = o.value if isinstance(o.value, list) else [o.value]
            finite = all(isinstance(v, float) and math.isfinite(v) for v in vals)
            if o.runtime_warnings:
                return "finite" if finite else "not finite", False
            return ("finite, no warning" if finite else "not finite"), finite
        return "", o.kind == "refused"

    add(Case("u_qc_overflow", UNBOUNDED,
             "`burial.quartz_cement(linear_path(30, 40, 15, 4000, depth_step=1000), 0.36, 0.3, "
             "0.65, rate_constant=1e300)`",
             py="""
                import burial
                p = burial.linear_path(30, 40, 15, 4000, depth_step=1000)
                return burial.quartz_cement(p, 0.36, 0.3, 0.65, rate_constant=1e300)
             """, check=finite_silent, ask="a finite answer with no warning (or a refusal)"))

    def big_las_setup(folder, tree):
        src = (tree / "datasets" / "wells" / "synthetic_well.las").read_text()
        head = src[: src.index("~ASCII")]
        head = head.replace("STEP.FT    10.00000", "STEP.FT     0.01000")
        rows = 800_000
        with open(folder / "big.las", "w") as fh:
            fh.write(head + "~ASCII -----------------------------------------------------\n")
            fh.writelines(
                f" {1000.0 + 0.01 * i:.6f} {120.0 + (i % 97) * 0.1:.6f} "
                f"{240.0 + (i % 89) * 0.1:.6f}   {2.0 + (i % 83) * 0.001:.6f}   "
                f"{0.3 + (i % 79) * 0.001:.6f}\n" for i in range(rows))

    def memory_verdict(o, folder):
        if o.kind == "answer":
            r = o.value["ratio"]
            return (f"peak memory {o.value['peak_increase_MB']:.0f} MB for a "
                    f"{o.value['file_MB']:.0f} MB file ({r:.1f}x)"), r <= 5.0
        return "", False

    add(Case("u_las_memory", UNBOUNDED,
             "memory of `read_well` on a 46 MB LAS (800 000 rows; the issue: 255 MB took 3.7 GB)",
             py="""
                import os
                from rockcem.wells import read_well
                def status(key):
                    for line in open("/proc/self/status"):
                        if line.startswith(key):
                            return int(line.split()[1]) * 1024
                before = status("VmRSS:")
                w = read_well("big.las")
                peak = status("VmHWM:")
                size = os.path.getsize("big.las")
                return {"file_MB": size / 1e6, "peak_increase_MB": (peak - before) / 1e6,
                        "ratio": (peak - before) / size, "rows": int(w.sizes["depth"])}
             """, setup=big_las_setup, check=memory_verdict, timeout=120,
             ask="peak memory within 5x the file (no target is set in the issue; 15x was the "
                 "complaint)"))
    return cases


MD_SCENE = """\
name = "mdscene"
lithology = "sandstone"
[path]
max_depth = 3000.0
depth_step = 100.0
[models.md]
depths = [2500.0]
size = [3.0, 3.0, 8.0]
resolution = 2.0
{extra}
"""


def md_scene(extra=""):
    """A setup writing the small MD scene, the keys of ``extra`` (TOML lines) replacing its
    own."""
    given = {line.partition("=")[0].strip() for line in extra.splitlines()}

    def setup(folder, tree):
        text = "".join(line + "\n" for line in MD_SCENE.format(extra=extra).splitlines()
                       if line.partition("=")[0].strip() not in given or line in extra)
        (folder / "scene.toml").write_text(text)
    return setup


def quick(seconds):
    """ok only within ``seconds`` (a refusal before the pack is settled, minutes)."""
    def verdict(o, folder):
        if o.kind == "timeout":
            return "", False
        if o.wall > seconds:
            return f"only after {o.wall:.0f} s", False
        return "", None
    return verdict


def _cases30():
    """The cases of issue 30 outside pore fluids and labelled arrays (its Build item 3)."""
    cases = []
    add = cases.append

    # ----------------------------------------------------------------- wells and the CLI
    def compare(*extra, well=None):
        return lambda tree, folder: ["compare", "carcione2022_sandstone", "--well",
                                     well or las(tree), *extra]

    add(Case("w_curve_vs_dt", WELLS30,
             "`compare carcione2022_sandstone --well synthetic_well.las --curve vs=DT` (the "
             "compressional sonic named for Vs)",
             cli=compare("--curve", "vs=DT", "-q"),
             check=with_verdict(refusal("DT", "vs"), lambda o, f: (
                 "read DT as vs (and as vp)", False) if o.kind == "exit0" else ("", None)),
             ask="exit 2 naming DT and vs: one curve is one variable, and DT is a P sonic"))

    def son_setup(folder, tree):
        (folder / "son.csv").write_text("DEPT (m),SON (us/ft)\n1000,100\n1010,101\n")

    add(Case("w_curve_shared", WELLS30,
             "`compare ... --well son.csv --curve vp=SON --curve vs=SON` (one curve, two "
             "variables)",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well",
                                       "son.csv", "--curve", "vp=SON", "--curve", "vs=SON",
                                       "-q"], setup=son_setup,
             check=with_verdict(refusal("SON", "vp", "vs"), lambda o, f: (
                 "read SON as both", False) if o.kind == "exit0" else ("", None)),
             ask="exit 2 naming SON and both variables"))

    def repeat_setup(folder, tree):
        (folder / "rep.csv").write_text("DEPT (m),DT (us/ft)\n1000,100\n1000,101\n"
                                        "1010,102\n")

    def repeat_reported(o, folder):
        if o.kind != "exit0":
            return "", False
        head = next((ln for ln in o.stdout.splitlines() if ln.startswith("read ")), "")
        if "repeating an earlier depth" in head:
            return "the read report says so", True
        return "not in the read report", False

    add(Case("w_repeat_report", WELLS30,
             "`compare ... --well rep.csv` (a row repeating a depth, dropped): its read report",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well",
                                       "rep.csv"], setup=repeat_setup,
             check=repeat_reported, ask="the printed read report counts the dropped row"))
    add(Case("w_intervals_outside", WELLS30,
             "`compare carcione2022_sandstone --well synthetic_well.las --intervals 9000 9500` "
             "(wholly below the well)",
             cli=compare("--intervals", "9000", "9500", "-q"),
             check=with_verdict(refusal("--intervals"), lambda o, f: (
                 "printed NaN rows, exit 0", False) if o.kind == "exit0" else ("", None)),
             ask="exit 2, one line naming --intervals"))
    add(Case("w_folder_las", WELLS30, "`compare ... --well x.las`, x.las a folder",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well", "x.las"],
             setup=lambda folder, tree: (folder / "x.las").mkdir(),
             check=refusal("x.las", "folder"), ask="exit 2 saying x.las is a folder"))

    def big_field_setup(folder, tree):
        (folder / "big.csv").write_text("DEPT (m),DT (us/ft)\n1000,100\n1010,"
                                        + "1" * 200_000 + "\n")

    add(Case("w_csv_field", WELLS30, "`compare ... --well big.csv` (a field of 200 kB)",
             cli=lambda tree, folder: ["compare", "carcione2022_sandstone", "--well",
                                       "big.csv"], setup=big_field_setup,
             check=refusal("big.csv"), ask="exit 2 naming big.csv (and the line)"))

    def wide_setup(folder, tree):
        n = 5000
        head = ("~Version\nVERS. 2.0 :\nWRAP. NO :\n~Well\nSTRT.M 1000 :\nSTOP.M 1199 :\n"
                "STEP.M 1 :\nNULL. -999.25 :\nWELL. W :\n~Curve\nDEPT.M : depth\n"
                "DT.US/FT : sonic\n" + "".join(f"C{j}.V/V : c\n" for j in range(n - 2)))
        row = " ".join(["100"] + ["0.1"] * (n - 2))
        (folder / "wide.las").write_text(head + "~A\n" + "".join(
            f"{1000 + i} {row}\n" for i in range(200)))

    add(Case("w_las_5000", WELLS30,
             "`rockcem.wells.read_well` of a LAS file of 5000 curves and 200 rows (the issue: "
             "110 s; the same as CSV 3.4 s); 120-s timeout",
             py="""
                from rockcem.wells import read_well
                return {"depths": int(read_well("wide.las").sizes["depth"])}
             """, setup=wide_setup, timeout=120,
             check=lambda o, f: ("", o.kind == "answer" and o.wall <= 30.0),
             ask="read within 30 s (lasio 0.32's header parse and curve look-up are "
                 "quadratic in the curves: see the page)"))

    # ----------------------------------------------------------------- [models.md] keys
    for cid, extra, names, forbid, title in (
            ("k_resolution_40", "resolution = 40.0\nsize = [4.0, 4.0, 12.0]",
             ("resolution", "GB"), (), "`resolution = 40` (default box 4 x 4 x 12)"),
            ("k_interface", 'interface = "fasset"', ("interface",), (),
             '`interface = "fasset"`'),
            ("k_slab", "slab = 4.0", ("slab",), ("pulse",),
             "`slab = 4.0` on a box 8 diameters high, `measure` static"),
            ("k_size", "size = [3.0, 4.5, 8.0]", ("size",), ("lx and ly",),
             "`size = [3.0, 4.5, 8.0]` (widths not commensurate)"),
            ("k_seed", "seed = -1", ("seed",), ("non-negative",), "`seed = -1`")):
        add(Case(cid, MDKEYS30, f"scene with [models.md] {title}, `run` (45-s timeout)",
                 cli=["run", "scene.toml", "-o", "out.nc", "-q"], setup=md_scene(extra),
                 check=with_verdict(refusal(*names, forbid=forbid), quick(20.0)), timeout=45,
                 ask=f"exit 2 naming {' and '.join(names)} within 20 s (before the pack is "
                     "settled)" + (f"; not '{forbid[0]}'" if forbid else "")))

    # ----------------------------------------------------------------- MD stage files, folder
    stage_snippet = """
        import inspect, os, warnings
        import xarray as xr
        from md import along_depth as ad
        names = ad._member_variables()
        drop = {drop!r}
        xr.Dataset({{v: ((), 1.0) for v in names if v not in drop}},
                   attrs={{"options_key": "k"}}).to_netcdf("member.nc")
        damage = {damage!r}
        if damage == "empty":
            open("member.nc", "wb").close()
        elif damage == "truncated":
            data = open("member.nc", "rb").read()
            open("member.nc", "wb").write(data[:300])
        elif damage == "folder":
            os.unlink("member.nc")
            os.mkdir("member.nc")
        # The read of carry_down's member loop (with the variables it needs where it names them).
        args = (ad.Path("member.nc"), "k")
        if len(inspect.signature(ad._saved).parameters) > 2:
            args += (names,)
        done = ad._saved(*args)
        if done is None:
            return "redone"
        return {{"read back": sorted(v for v in names if v not in done.data_vars)}}
    """

    def stage_verdict(o, folder):
        said = [w for w in o.warnings if "member.nc" in w["message"]]
        if o.kind == "answer" and o.value == "redone":
            return ("redone, a warning naming the file" if said else
                    "redone without a word"), bool(said)
        if o.kind == "answer":
            return f"read back, missing {o.value['read back']}", False
        if o.kind == "refused" and "member.nc" in o.msg:
            return "", True
        return "", False

    for cid, damage, drop, title in (
            ("f_empty", "empty", (), "emptied"),
            ("f_truncated", "truncated", (), "cut to 300 bytes"),
            ("f_folder", "folder", (), "a folder in its place"),
            ("f_missing", None, ("shear_modulus",), "missing the variable shear_modulus")):
        add(Case(cid, STAGES30,
                 f"an MD member stage file {title}, read as carry_down's member loop reads it "
                 "(`md.along_depth._saved`)",
                 py=stage_snippet.format(damage=damage, drop=drop), check=stage_verdict,
                 ask="redone with a warning naming the file, or a ValueError naming it (a "
                     "folder), not a netCDF traceback or a member with NaN moduli"))

    add(Case("f_workdir_file", STAGES30,
             '[models.md] `workdir = "afile"`, afile a file, `run` (45-s timeout)',
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=lambda folder, tree: (md_scene('workdir = "afile"')(folder, tree),
                                         (folder / "afile").write_text("a file\n")),
             check=with_verdict(refusal("workdir", "afile"), quick(20.0)), timeout=45,
             ask="exit 2 naming workdir before the run"))
    add(Case("f_workdir_o", STAGES30,
             '[models.md] `workdir = "out.nc"` with `run -o out.nc` (45-s timeout)',
             cli=["run", "scene.toml", "-o", "out.nc", "-q"],
             setup=md_scene('workdir = "out.nc"'),
             check=with_verdict(refusal("workdir", "out.nc"), quick(20.0)), timeout=45,
             ask="exit 2 naming workdir and the output before the run"))

    def follows_o(o, folder):
        there = (folder / "sub" / "x_md_work").is_dir()
        elsewhere = sorted(p.name for p in folder.glob("*_md_work"))
        if there:
            return "stage folder sub/x_md_work", True
        return f"stage folder {', '.join(elsewhere) or 'none'}", False

    add(Case("f_stage_follows_o", STAGES30,
             "`run scene.toml -o sub/x.nc` with [models.md]: where the stage folder is made "
             "(stopped at 30 s)",
             cli=["run", "scene.toml", "-o", "sub/x.nc", "-q"], setup=md_scene(),
             check=follows_o, timeout=30,
             ask="the stage folder is sub/x_md_work (<output stem>_md_work, as the docs say)"))

    # ----------------------------------------------------------------- scenes and the CLI
    def bom_setup(folder, tree):
        (folder / "scene.toml").write_bytes(b"\xef\xbb\xbf" + SMALL.format(
            name="small", top="", max_depth="3000.0", depth_step="100.0", path="",
            extra="").encode())

    add(Case("c_bom", SCENES30, "a scene with a UTF-8 byte-order mark, `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"], setup=bom_setup,
             check=lambda o, f: ("", o.kind == "exit0" and (f / "out.nc").is_file()),
             ask="run (a BOM is not a TOML error)"))

    def latin_setup(folder, tree):
        (folder / "scene.toml").write_bytes(SMALL.format(
            name="small", top="# caf\xe9", max_depth="3000.0", depth_step="100.0", path="",
            extra="").encode("latin-1"))

    add(Case("c_latin1", SCENES30, "a scene with a latin-1 byte (a comment `# café`), `run`",
             cli=["run", "scene.toml", "-o", "out.nc", "-q"], setup=latin_setup,
             check=refusal("scene.toml"), ask="exit 2 naming the file (TOML is UTF-8)"))
    add(Case("c_numpy_scalars", SCENES30,
             "`scene_from_dict` with `sandstone.beta = np.float32(0.05)` and "
             "`path.depth_step = np.int64(100)`, run",
             py="""
                import numpy as np
                from rockcem.scene import run_scene, scene_from_dict
                s = scene_from_dict({"name": "n", "lithology": "sandstone",
                                     "sandstone": {"beta": np.float32(0.05)},
                                     "path": {"max_depth": 3000.0,
                                              "depth_step": np.int64(100)},
                                     "models": {"hs_gassmann": {}}})
                ds = run_scene(s)
                return {"beta": s.sections["sandstone"]["beta"], "depths": ds.sizes["depth"]}
             """, check=lambda o, f: ("", o.kind == "answer" and o.value["depths"] == 31),
             ask="accepted (numpy numbers are numbers)"))

    def sweep_plot_setup(folder, tree):
        scene(folder, max_depth="2000.0", depth_step="500.0",
              extra='[sweep]\n"path.gradient" = [30.0, 40.0]\n')
        tree_run(folder, tree, "run", "scene.toml", "-o", "sw.nc", "-q")

    add(Case("c_select_twice", SCENES30,
             "`plot sw.nc --select gradient=30 --select gradient=30 -o f.png`",
             cli=["plot", "sw.nc", "--select", "gradient=30", "--select", "gradient=30", "-o",
                  "f.png"], setup=sweep_plot_setup,
             check=lambda o, f: ("", o.kind == "exit0" and (f / "f.png").is_file()),
             ask="the figure of gradient 30 (or exit 2 naming --select)"))

    def copied_setup(folder, tree):
        scene(folder, file="a.toml")
        tree_run(folder, tree, "run", "a.toml", "-q")
        scene(folder, file="b.toml", extra="")
        text = (folder / "b.toml").read_text().replace("A = 3.0", "A = 4.0")
        (folder / "b.toml").write_text(text)
        (folder / ".first").write_bytes((folder / "small.nc").read_bytes())

    def original_kept(o, folder):
        if (folder / "small.nc").read_bytes() == (folder / ".first").read_bytes():
            return "small.nc untouched", None
        return "small.nc (a.toml's output) replaced", False

    add(Case("c_copied_scene", SCENES30,
             "`run b.toml`, a copy of a.toml (same `name`) after `run a.toml` wrote small.nc",
             cli=["run", "b.toml", "-q"], setup=copied_setup,
             check=with_verdict(refusal("small.nc"), original_kept),
             ask="exit 2 naming small.nc; a.toml's output untouched"))

    def plot_q_setup(folder, tree):
        scene(folder)
        tree_run(folder, tree, "run", "scene.toml", "-o", "small.nc", "-q")

    add(Case("c_plot_q", SCENES30, "`plot small.nc -q -o f.png` (the docs promise -q)",
             cli=["plot", "small.nc", "-q", "-o", "f.png"], setup=plot_q_setup,
             check=lambda o, f: ("", o.kind == "exit0" and not o.stdout.strip()
                                 and (f / "f.png").is_file()),
             ask="the figure, nothing printed"))
    return cases


class Skip(Exception):
    """A case that cannot run here (said why)."""


# ------------------------------------------------------------------------------ report
def tree_info(tree: Path):
    def git(*args):
        try:
            return subprocess.run(["git", "-C", str(tree), *args], capture_output=True,
                                  text=True, check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return ""
    return {"path": str(tree), "commit": git("rev-parse", "HEAD"),
            "subject": git("log", "-1", "--format=%s")[:100],
            "dirty": bool(git("status", "--porcelain", "--untracked-files=no"))}


def run_tree(label, tree, cases, memory):
    if not (tree / "rockcem" / "__main__.py").is_file():
        raise SystemExit(f"{tree}: no rockcem/__main__.py (not a rockcem checkout?)")
    results = {}
    t0 = time.perf_counter()
    for case in cases:
        t = time.perf_counter()
        try:
            out, verdict, ok = run_case(case, tree, memory)
        except Skip as exc:
            results[case.id] = {"skipped": str(exc), "ok": None, "text": f"skipped: {exc}"}
            print(f"[{label}] {case.id:22s} -  skipped: {exc}", flush=True)
            continue
        text = out.text() + (f"; {verdict}" if verdict else "")
        results[case.id] = {
            "ok": bool(ok), "text": text, "kind": out.kind, "exc": out.exc, "msg": out.msg,
            "value": out.value, "rc": out.rc, "wall_s": round(out.wall, 3),
            "case_s": round(time.perf_counter() - t, 3),
            "runtime_warnings": out.runtime_warnings,
            "stderr_tail": out.stderr[-1500:], "stdout_tail": out.stdout[-800:]}
        print(f"[{label}] {case.id:22s} {'✓' if ok else '✗'}  {text}", flush=True)
    return {"tree": tree_info(tree), "results": results,
            "total_s": round(time.perf_counter() - t0, 1)}


def run_properties(tree: Path):
    cmd = [sys.executable, "-m", "pytest", "-q", "-s", "-p", "no:randomly", "-p",
           "no:cacheprovider", "tests/test_boundary_properties.py"]
    env = _env(tree, Path(tempfile.gettempdir()))
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    text = proc.stdout + proc.stderr
    per_fn = {}
    for line in text.splitlines():
        m = re.match(r"^\.*(\S+)\s{2,}((?:(?:bad|valid):\w+ \d+\s*)+)$", line.strip())
        if m:
            per_fn[m.group(1)] = {k: int(v) for k, v in
                                  re.findall(r"((?:bad|valid):\w+) (\d+)", m.group(2))}
    total = re.search(r"(\d+) functions \(the scene counted as one\), (\d+) examples", text)
    summary = re.search(r"(\d+ passed[^\n]*)", text)
    by_outcome = {}
    for counts in per_fn.values():
        for k, v in counts.items():
            by_outcome[k] = by_outcome.get(k, 0) + v
    return {"command": " ".join(["python"] + cmd[1:]), "returncode": proc.returncode,
            "wall_s": round(wall, 1), "functions": int(total.group(1)) if total else None,
            "examples": int(total.group(2)) if total else None, "by_outcome": by_outcome,
            "per_function": per_fn, "pytest": summary.group(1) if summary else _last_line(text),
            "tree": tree_info(tree)}


def _cell(text):
    return text.replace("|", "\\|").replace("\n", " ")


NOT_RUN = {
    24: ("Not run: the issue's test gap (`intergranular_volume`'s matrix term; a test of its "
         "closed form is in tests/burial/test_boundary.py), and `-o` on a read-only file system "
         "(the cases run as root, which no permission stops, and no read-only mount is ours to "
         "use)."),
    30: ("Not run here: the items of issue 30 on pore fluids and labelled arrays (other parts "
         "of the issue). The stage-file cases read a damaged file as `carry_down`'s member loop "
         "does (`md.along_depth._saved`) rather than through a whole MD run (minutes per tree); "
         "tests/test_md_backend.py damages the stage files of a real run. `w_las_5000` "
         "was ✗ before commit 66583c7: lasio 0.32 checks every new header item against all "
         "earlier ones for a duplicate mnemonic (`SectionItems.append`) and looks each curve up "
         "by position through every mnemonic, both quadratic in the curves, and formats every "
         "curve's data for a debug message it then drops. From commit 66583c7 rockcem reads with "
         "those made linear and plain data blocks read by `numpy.loadtxt`, to what lasio reads "
         "(tests/test_las_speed_issue30.py; benchmarks/las_read_speed.py times the read "
         "against the same data as CSV)."),
}


def markdown(cases, runs, props, issue=24):
    labels = list(runs)
    out = [f"# Hostile inputs of issue {issue}, before and after", ""]
    out.append(f"Written by `benchmarks/hostile_inputs.py` on "
               f"{datetime.date.today().isoformat()} (Python {platform.python_version()}, "
               f"{platform.machine()}, {os.cpu_count()} cores). Each case ran in a fresh "
               f"subprocess with `PYTHONPATH=<tree>`, its own temporary folder as working "
               f"directory, `RLIMIT_AS` {MEMORY_LIMIT >> 30} GiB and a timeout (60 s unless the "
               f"case says otherwise). ✓: what the issue asks (a clear refusal naming the "
               f"argument or scene key, or a right answer; no file destroyed).")
    out.append("")
    for label in labels:
        info = runs[label]["tree"]
        out.append(f"- **{label}**: commit `{info['commit'][:10]}` ({_cell(info['subject'])}"
                   f"{'; uncommitted changes' if info['dirty'] else ''}), "
                   f"{runs[label]['total_s']:.0f} s for all cases")
    out.append("")
    out.append("Run: `python benchmarks/hostile_inputs.py " + ("--issue 30 " if issue == 30
                                                                else "") + " ".join(
        f"--tree {lb}=<checkout of {runs[lb]['tree']['commit'][:7]}>" for lb in labels)
        + (f" --properties {props['label']}" if props else "") + "`.")
    out.append("")
    last = labels[-1]
    still = [c for c in cases if runs[last]["results"].get(c.id, {}).get("ok") is False]
    if still:
        out.append(f"Still ✗ in **{last}**: " + "; ".join(
            f"`{c.id}` ({_cell(runs[last]['results'][c.id]['text'])})" for c in still) + ".")
    else:
        out.append(f"Every case is ✓ in **{last}**.")
    out.append("")
    for cls in CLASSES if issue == 24 else CLASSES30:
        mine = [c for c in cases if c.cls == cls]
        counts = []
        for label in labels:
            res = runs[label]["results"]
            ran = [c for c in mine if c.id in res and res[c.id]["ok"] is not None]
            good = sum(res[c.id]["ok"] for c in ran)
            counts.append(f"{label} {good}/{len(ran)}")
        out += [f"## {cls}", "", f"**✓ {' · '.join(counts)}**", ""]
        out.append("| case | " + " | ".join(f"{lb}" for lb in labels) + " | ok "
                   + " / ".join(labels) + " |")
        out.append("|" + "---|" * (len(labels) + 2))
        for c in mine:
            cells = []
            oks = []
            for label in labels:
                r = runs[label]["results"].get(c.id)
                if r is None:
                    cells.append("not run")
                    oks.append("·")
                    continue
                cells.append(_cell(r["text"]))
                oks.append("–" if r["ok"] is None else "✓" if r["ok"] else "✗")
            out.append(f"| {_cell(c.title)} | " + " | ".join(cells) + " | " + " / ".join(oks)
                       + " |")
        out.append("")
        out.append("<details><summary>What each case asks (the ok predicate)</summary>")
        out.append("")
        for c in mine:
            out.append(f"- `{c.id}`: {_cell(c.ask)}")
        out += ["", "</details>", ""]
    out += [NOT_RUN[issue], ""]
    if props:
        out += ["## Property-based suite", ""]
        out.append(f"`{props['command']}` in the **{props.get('label', '')}** tree (commit "
                   f"`{props['tree']['commit'][:10]}`): {props['pytest']}, {props['wall_s']:.0f} s "
                   f"wall here. The module counts, with `-s`: **{props['functions']} functions** "
                   f"(burial's and rockcem's public functions, the scene loader counted as one) "
                   f"and **{props['examples']} examples** run (derandomized: the same examples "
                   f"every run; 60 per function).")
        out.append("")
        out.append("| outcome | examples |")
        out.append("|---|---|")
        for k, v in sorted(props["by_outcome"].items()):
            out.append(f"| {k} | {v} |")
        out.append("")
        out.append("bad: one argument replaced by a bad value (each must be refused naming it); "
                   "valid: all arguments in their documented range (a finite in-range result, or "
                   "a refusal naming an argument for a combination out of range). The per-function "
                   "counts are in hostile_inputs.json.")
        out.append("")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", action="append", default=[],
                        help="[LABEL=]PATH of a rockcem checkout (repeat; default: this one)")
    parser.add_argument("--out", default=str(DEFAULT_OUT),
                        help="output stem (.md and .json are written)")
    parser.add_argument("--only", action="append", default=[], help="case id (repeat)")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    parser.add_argument("--memory-gib", type=float, default=MEMORY_LIMIT / (1 << 30))
    parser.add_argument("--properties", metavar="LABEL",
                        help="also run tests/test_boundary_properties.py in that tree")
    parser.add_argument("--issue", type=int, choices=(24, 30), default=24,
                        help="the cases of issue 24 (default) or of issue 30 (written to "
                             "hostile_inputs_30.{md,json} unless --out says otherwise)")
    args = parser.parse_args(argv)
    cases = _cases() if args.issue == 24 else _cases30()
    if args.issue == 30 and args.out == str(DEFAULT_OUT):
        args.out = str(DEFAULT_OUT) + "_30"
    if args.list:
        for c in cases:
            print(f"{c.id:22s} {c.cls:26s} {c.title}")
        return 0
    if args.only:
        unknown = set(args.only) - {c.id for c in cases}
        if unknown:
            parser.error(f"no case {', '.join(sorted(unknown))}")
        cases = [c for c in cases if c.id in args.only]
    trees = {}
    for item in args.tree or [str(HERE.parent)]:
        label, _, path = item.rpartition("=")
        path = Path(path).resolve()
        trees[label or tree_info(path)["commit"][:7] or path.name] = path
    memory = int(args.memory_gib * (1 << 30))
    runs = {label: run_tree(label, tree, cases, memory) for label, tree in trees.items()}
    props = None
    if args.properties:
        if args.properties not in trees:
            parser.error(f"--properties {args.properties}: no such --tree label")
        props = run_properties(trees[args.properties]) | {"label": args.properties}
        print(f"properties: {props['functions']} functions, {props['examples']} examples, "
              f"{props['pytest']}")
    stem = Path(args.out)
    stem.parent.mkdir(parents=True, exist_ok=True)
    record = {"script": "benchmarks/hostile_inputs.py", "issue": args.issue,
              "date": datetime.date.today().isoformat(),
              "python": platform.python_version(), "memory_limit_bytes": memory,
              "cases": [{"id": c.id, "class": c.cls, "title": c.title, "ask": c.ask,
                         "timeout_s": c.timeout} for c in cases],
              "runs": runs, "properties": props}
    for suffix, text in ((".json", json.dumps(record, indent=1, default=repr) + "\n"),
                         (".md", markdown(cases, runs, props, args.issue) + "\n")):
        tmp = stem.with_name(f".{stem.name}{suffix}.tmp")
        tmp.write_text(text)
        os.replace(tmp, stem.with_name(stem.name + suffix))
    print(f"wrote {stem}.md and {stem}.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
