"""`rockcem run --scheduler ADDRESS`: an address where no dask scheduler answers is refused in
one line before the run, within a few seconds (issue 24: a traceback after 30 s)."""

import socket
import threading
import time

import pytest

from rockcem._scheduler import SCHEDULER_CONNECT_TIMEOUT_S
from rockcem._scheduler import check_scheduler as _check_scheduler
from rockcem.cli import main

SWEEP = """name = "sw"
lithology = "shale"
outputs = ["porosity"]
[path]
max_depth = 1000.0
depth_step = 250.0
[sweep]
"path.gradient" = [20.0, 30.0]
"""


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def garbage_server():
    """A TCP server that is not dask: it answers every connection with 16 bytes of 0xff."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen()
    srv.settimeout(0.2)
    stop = threading.Event()

    def serve():
        while not stop.is_set():
            try:
                conn, _ = srv.accept()
            except OSError:
                continue
            with conn:
                conn.sendall(b"\xff" * 16)
                time.sleep(0.5)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield srv.getsockname()[1]
    stop.set()
    thread.join()
    srv.close()


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:{port}", "127.0.0.1:{port}"])
def test_nothing_listening_is_one_line_before_the_run(tmp_path, capsys, monkeypatch, address):
    from rockcem import scene

    def refuse(*args, **kwargs):
        raise AssertionError("the scene ran before the scheduler was checked")

    monkeypatch.setattr(scene, "run_scene", refuse)
    (tmp_path / "sw.toml").write_text(SWEEP)
    address = address.format(port=_free_port())
    start = time.monotonic()
    code = main(["run", str(tmp_path / "sw.toml"), "-o", str(tmp_path / "sw.nc"),
                 "--scheduler", address])
    assert time.monotonic() - start < SCHEDULER_CONNECT_TIMEOUT_S
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("rockcem: error: --scheduler ") and err.count("\n") == 1, err
    assert "no dask scheduler answers" in err and "--scheduler local" in err
    assert not (tmp_path / "sw.nc").exists()


def test_a_server_that_is_not_dask_is_refused(garbage_server):
    start = time.monotonic()
    with pytest.raises(ValueError, match="something listens there, but not a dask scheduler"):
        _check_scheduler(f"tcp://127.0.0.1:{garbage_server}")
    assert time.monotonic() - start < 2 * SCHEDULER_CONNECT_TIMEOUT_S + 1


@pytest.mark.parametrize("address", ["tcp://host", "tcp://host:port", "nonsense::", ":8786",
                                     "tcp://[::1:8786", "[::1"])
def test_malformed_address(address):
    with pytest.raises(ValueError, match=r"expected 'local' or a dask scheduler address"):
        _check_scheduler(address)


def test_a_dask_scheduler_and_local_pass():
    distributed = pytest.importorskip("distributed")
    _check_scheduler(None)
    _check_scheduler("local")
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as c:
        _check_scheduler(c.scheduler_address)


def test_run_scene_from_python_refuses_a_dead_address_at_once(monkeypatch):
    """Issue 24: run_scene(scheduler="tcp://...") from Python waited 30 s for dask's client."""
    from rockcem import runner
    from rockcem.scene import run_scene, scene_from_dict
    import tomllib

    def never(*args, **kwargs):
        raise AssertionError("the scene ran before the scheduler was checked")

    monkeypatch.setattr(runner, "run", never)
    scene = scene_from_dict(tomllib.loads(SWEEP))
    start = time.monotonic()
    with pytest.raises(ValueError, match=r"^scheduler tcp://127\.0\.0\.1:\d+: no dask scheduler "
                                         r"answers .*scheduler='local'"):
        run_scene(scene, scheduler=f"tcp://127.0.0.1:{_free_port()}")
    assert time.monotonic() - start < SCHEDULER_CONNECT_TIMEOUT_S
    for bad in ("", 8786, ["local"]):
        with pytest.raises(ValueError, match="expected 'local' or a dask scheduler address"):
            run_scene(scene, scheduler=bad)


def test_run_md_scene_refuses_a_dead_address_before_any_pack(tmp_path):
    from md.experiment import md_scene_from_dict, run_md_scene

    scene = md_scene_from_dict({"name": "m", "md": {}})
    with pytest.raises(ValueError, match="no dask scheduler answers"):
        run_md_scene(scene, workdir=tmp_path / "w", scheduler=f"127.0.0.1:{_free_port()}")
    assert not (tmp_path / "w").exists()


def test_check_works_inside_a_running_event_loop_and_for_tls(garbage_server):
    """A notebook runs its cells inside an event loop; asyncio.run() refused there. A tls://
    address is checked as far as its socket (dask's TLS handshake needs its security config)."""
    import asyncio

    async def in_a_loop():
        with pytest.raises(ValueError, match="not a dask scheduler"):
            _check_scheduler(f"tcp://127.0.0.1:{garbage_server}")
        _check_scheduler(f"tls://127.0.0.1:{garbage_server}")       # listening: passes
        with pytest.raises(ValueError, match="no dask scheduler answers"):
            _check_scheduler(f"tls://127.0.0.1:{_free_port()}")

    asyncio.run(in_a_loop())
