"""Independent MD tasks run serially, on local processes or on a dask.distributed cluster.

One mechanism for the MD study members (:mod:`md.experiment`) and the MD depths of a burial
scene (:mod:`md.along_depth`): ``scheduler=None`` with ``jobs=1`` runs in this process,
``jobs > 1`` on that many spawned local processes, ``scheduler="local"`` on a local dask cluster
of ``jobs`` (at least 2) single-threaded worker processes, and any other string is the address
of a running dask scheduler (``tcp://host:8786``). Tasks read their packs from and write their
results to stage files, so the workers must see the work folder (one machine, or a shared
file system).
"""

from __future__ import annotations

__all__ = ["run_tasks"]


def run_tasks(fn, tasks, *, scheduler=None, jobs=1, progress=False, desc="tasks"):
    """Yield ``(task, fn(*task))`` for every tuple of arguments in ``tasks``, as they finish.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled to the workers).
    tasks : list of tuple
    scheduler : str, optional
        None, ``"local"`` or a dask scheduler address.
    jobs : int
        Local processes (``>= 1``); with ``scheduler="local"`` the number of dask workers.
    progress : bool
        A progress bar (tqdm) over the tasks.
    """
    from tqdm.auto import tqdm

    if isinstance(jobs, bool) or int(jobs) != jobs or jobs < 1:
        raise ValueError(f"jobs must be an integer >= 1; got {jobs!r}")
    tasks = list(tasks)
    bar = tqdm(total=len(tasks), disable=not progress or not tasks, desc=desc, unit="task")
    try:
        if scheduler is not None:
            yield from _dask(fn, tasks, scheduler, int(jobs), bar)
        elif jobs <= 1 or len(tasks) <= 1:
            for task in tasks:
                yield task, fn(*task)
                bar.update()
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor, as_completed

            # "spawn": a fresh interpreter per process (no copy of a parent's numba threads).
            with ProcessPoolExecutor(max_workers=min(int(jobs), len(tasks)),
                                     mp_context=multiprocessing.get_context("spawn")) as pool:
                futures = {pool.submit(fn, *task): task for task in tasks}
                for fut in as_completed(futures):
                    yield futures[fut], fut.result()
                    bar.update()
    finally:
        bar.close()


def _dask(fn, tasks, scheduler, jobs, bar):
    from rockcem._scheduler import dask_client

    if not isinstance(scheduler, str) or not scheduler:
        raise ValueError(f"scheduler must be 'local' or a dask scheduler address; "
                         f"got {scheduler!r}")
    with dask_client(scheduler, max(jobs, 2), what="running MD tasks on dask") as client:
        from dask.distributed import as_completed

        futures = {client.submit(fn, *task, pure=False): task for task in tasks}
        for fut in as_completed(futures):
            yield futures[fut], fut.result()
            bar.update()
