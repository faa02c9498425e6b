"""Where the work of a run goes: the check of a dask scheduler address, and the one client.

Every entry point that takes ``scheduler`` (``rockcem run --scheduler``,
:func:`rockcem.scene.run_scene`, :func:`md.experiment.run_md_scene`) calls
:func:`check_scheduler` before any work, so an address where no scheduler answers is refused in
one line within :data:`SCHEDULER_CONNECT_TIMEOUT_S` (dask's own client waits 30 s, and only when
the first task is sent); :func:`dask_client` is the client both the sweep runner and the MD task
runner use.
"""

from __future__ import annotations

from contextlib import contextmanager

__all__ = ["SCHEDULER_CONNECT_TIMEOUT_S", "check_scheduler", "dask_client"]

#: Seconds a scheduler address is given to answer before the run starts.
SCHEDULER_CONNECT_TIMEOUT_S = 5.0

_EXTRA = "pip install 'rockcem[dask]'"


def check_scheduler(address, *, name="scheduler"):
    """Refuse ``address`` before any work unless it is None, ``"local"`` or a TCP address
    (``tcp://host:port``, ``tls://...`` or ``host:port``) where a dask scheduler answers within
    :data:`SCHEDULER_CONNECT_TIMEOUT_S` (other dask protocols, such as ``inproc://``, are passed
    on as given).

    Raises ``ValueError`` naming ``name`` (the argument, or ``--scheduler`` on the command line)
    in one line: a malformed address, nothing listening, or something that is not dask.
    """
    if address is None or address == "local":
        return
    bad = ValueError(f"{name} {address!r}: expected 'local' or a dask scheduler address such "
                     "as tcp://host:8786")
    if not isinstance(address, str) or not address.strip():
        raise bad
    import asyncio
    import socket
    from urllib.parse import urlsplit

    where = address if "://" in address else f"tcp://{address}"
    try:
        url = urlsplit(where)
        host, port = url.hostname, url.port
    except ValueError:          # urlsplit itself refuses it ('tcp://[::1:8786')
        raise bad from None
    if url.scheme not in ("tcp", "tls"):
        return
    if not host or port is None:
        raise bad

    def refuse(reason):
        local = "--scheduler local" if name.startswith("--") else "scheduler='local'"
        return ValueError(f"{name} {address}: no dask scheduler answers at {host}:{port} "
                          f"({reason}); start one (`dask scheduler`) or use {local}")

    try:
        with socket.create_connection((host, port), timeout=SCHEDULER_CONNECT_TIMEOUT_S):
            pass
    except OSError as exc:
        raise refuse("timed out" if isinstance(exc, TimeoutError)
                     else (exc.strerror or str(exc))) from None
    try:
        from distributed.comm import connect
    except ImportError:
        raise ValueError(f"{name} needs the 'dask' extra: {_EXTRA}") from None
    if url.scheme == "tls":
        # dask's TLS handshake needs the security configuration the client will use; the
        # listening socket is as far as this check goes.
        return

    async def handshake():
        comm = await connect(where, timeout=SCHEDULER_CONNECT_TIMEOUT_S)
        await comm.close()

    def probe():
        asyncio.run(asyncio.wait_for(handshake(), 2 * SCHEDULER_CONNECT_TIMEOUT_S))

    # Something listens there: is it dask? (A server that is not can make dask's handshake read
    # a garbage length and ask for exabytes, or never answer.) In a thread of its own, so that
    # a caller inside a running event loop (a Jupyter notebook) can check too.
    from concurrent.futures import ThreadPoolExecutor

    try:
        with ThreadPoolExecutor(max_workers=1) as pool:
            pool.submit(probe).result()
    except (OSError, TimeoutError, MemoryError, ValueError) as exc:
        raise refuse(f"something listens there, but not a dask scheduler: "
                     f"{type(exc).__name__}") from None


@contextmanager
def dask_client(scheduler, workers, *, what="running on dask"):
    """A ``dask.distributed.Client``: on a new local cluster of ``workers`` single-threaded
    processes for ``scheduler="local"``, else connected to the scheduler at that address;
    closed (with its cluster) on exit."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise ValueError(f"{what} needs the 'dask' extra: {_EXTRA}") from None
    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    else:
        client = Client(scheduler, timeout=SCHEDULER_CONNECT_TIMEOUT_S)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
