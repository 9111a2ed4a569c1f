"""Where chunks run: threads in this process (default) or a Dask cluster.

Both take the same ``(index, runs)`` work items and call ``done(index, out)`` in the calling
thread as chunks finish, with a bounded number of chunks in flight (flat memory for any
number of runs).
"""

from __future__ import annotations

import os
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

from .design import SweepError
from .runner import run_chunk

__all__ = ["DEFAULT_CONNECT_TIMEOUT", "dask_client", "run_dask", "run_threads"]

DEFAULT_CONNECT_TIMEOUT = 10.0


def run_threads(job: dict, items, done, workers: int | None = None) -> None:
    """Run chunks on ``workers`` threads (default: all cores).

    The compiled integrator releases the GIL, so threads run in parallel; only the short
    per-run set-up (parsing the overrides, packing the parameters) is serial.
    """
    workers = max(1, workers or os.cpu_count() or 1)
    items = iter(items)
    if workers == 1:
        for index, runs in items:
            done(index, run_chunk(job, runs))
        return
    with ThreadPoolExecutor(workers, thread_name_prefix="clutchsim-sweep") as pool:
        pending = {}
        try:
            while True:
                while len(pending) < 2 * workers:
                    nxt = next(items, None)
                    if nxt is None:
                        break
                    pending[pool.submit(run_chunk, job, nxt[1])] = nxt[0]
                if not pending:
                    break
                finished, _ = wait(pending, return_when=FIRST_COMPLETED)
                for fut in sorted(finished, key=pending.get):
                    done(pending.pop(fut), fut.result())
        except BaseException:
            for fut in pending:
                fut.cancel()
            raise


def dask_client(address: str = "local", workers: int | None = None,
                connect_timeout: float = DEFAULT_CONNECT_TIMEOUT):
    """``(client, owned)``: a LocalCluster client for ``"local"``, else a client connected
    to the scheduler at ``address`` (a clear error if it does not answer in time)."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:   # pragma: no cover - dask is an optional extra
        raise SweepError("the Dask backend needs dask.distributed: pip install "
                         "'clutchsim[dask]'") from None
    if address == "local":
        # dashboard on a free port: with None, distributed (2026.8) still binds its HTTP
        # server to 8787 first, and a second cluster on the machine (two sweeps at once, two
        # test processes) warns and leaks the socket it tried
        cluster = LocalCluster(n_workers=max(1, workers or os.cpu_count() or 1),
                               threads_per_worker=1, processes=True, dashboard_address=":0")
        return Client(cluster), True
    if "://" not in address:
        raise SweepError(f"Dask address {address!r}: expected 'local' or a scheduler address "
                         "like tcp://HOST:8786")
    try:
        client = Client(address, timeout=connect_timeout)
    except (OSError, TimeoutError) as exc:
        raise SweepError(f"no Dask scheduler answered at {address} within "
                         f"{connect_timeout:g} s ({type(exc).__name__}); check the address "
                         "and that `dask scheduler` is running, or use --dask local") from None
    return client, True


def run_dask(job: dict, items, done, client, workers: int | None = None) -> None:
    """Run chunks as Dask tasks; results come back to this process, which writes them."""
    from distributed import as_completed
    limit = 2 * max(1, workers or sum(client.nthreads().values()) or 1)
    job_f = client.scatter(job, broadcast=True)
    items = iter(items)
    pending = {}

    def submit():
        nxt = next(items, None)
        if nxt is None:
            return None
        index, runs = nxt
        fut = client.submit(run_chunk, job_f, runs, pure=False,
                            key=f"clutchsim-sweep-{job['sweep_id'][:12]}-{index}")
        pending[fut.key] = (index, fut)
        return fut

    first = [f for f in (submit() for _ in range(limit)) if f is not None]
    if not first:
        return
    queue = as_completed(first)
    try:
        for fut in queue:
            index, _ = pending.pop(fut.key)
            out = fut.result()
            fut.release()
            done(index, out)
            nxt = submit()
            if nxt is not None:
                queue.add(nxt)
    except BaseException:
        client.cancel([f for _, f in pending.values()])
        raise
