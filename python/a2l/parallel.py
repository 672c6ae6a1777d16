"""Run independent rollouts: in this process, on local worker processes, or on Dask.

Every task carries its own seed, so results do not depend on where or in which order tasks
run: one worker, two workers and a Dask cluster give the same results.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Generic, TypeVar

T = TypeVar("T")
R = TypeVar("R")

__all__ = ["Executor", "Pending"]


class Executor:
    """Maps a picklable function over tasks, keeping the tasks' order.

    Parameters
    ----------
    workers : int
        Local worker processes; 1 runs everything in this process (the default, and the
        most debuggable).
    cluster : str or None
        Address of a Dask distributed scheduler (``"tcp://127.0.0.1:8786"``); when given,
        tasks run there and `workers` is ignored.

    Notes
    -----
    Local workers are started with the ``spawn`` method (PyBullet clients must not be
    inherited through ``fork``) once, and reused until :meth:`close`.
    """

    #: Batches per worker slot in one :meth:`map` (more than one balances uneven tasks).
    BATCHES_PER_SLOT = 4

    def __init__(self, workers: int = 1, cluster: str | None = None) -> None:
        if workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        self.workers = workers
        self.cluster = cluster
        self._pool: ProcessPoolExecutor | None = None
        self._client: Any = None
        if cluster:
            try:
                from dask.distributed import Client
            except ImportError as exc:  # pragma: no cover - dask is a dependency
                raise RuntimeError("--cluster needs dask[distributed]") from exc
            try:
                self._client = Client(cluster, timeout="10s")
            except OSError as exc:
                raise ConnectionError(
                    f"cannot reach the Dask scheduler at {cluster!r}: {exc}") from exc

    def map(self, fn: Callable[[T], R], tasks: Iterable[T],
            on_done: Callable[[int], None] | None = None,
            batches: int | None = None) -> list[R]:
        """``[fn(t) for t in tasks]``, computed where the executor runs things.

        Parameters
        ----------
        fn : callable
            A module-level (picklable) function.
        tasks : iterable
            Its arguments, one per call.
        on_done : callable, optional
            Called with the number of finished tasks (progress bars): after each task in
            this process, after each batch on workers or Dask, in task order.
        batches : int, optional
            As in :meth:`submit`.
        """
        return self.submit(fn, tasks, batches).result(on_done)

    @property
    def in_process(self) -> bool:
        """True when tasks run in this process (one worker, no cluster): a submitted map
        then runs only when its results are asked for."""
        return self._client is None and self.workers == 1

    def submit(self, fn: Callable[[T], R], tasks: Iterable[T],
               batches: int | None = None) -> Pending[R]:
        """Start ``[fn(t) for t in tasks]`` and return at once (:meth:`map` without the
        wait): the caller can submit the next tasks while these run, so that the workers
        do not wait for it between two maps.

        In this process (:attr:`in_process`) nothing runs before :meth:`Pending.result`.
        Elsewhere the tasks travel in at most `batches` contiguous batches (default
        :data:`BATCHES_PER_SLOT` per worker slot; ``len(tasks)`` for one task each, for
        long tasks of uneven length).
        """
        items: Sequence[T] = list(tasks)
        if not items or self.in_process:
            return Pending(fn, items, [], None)
        # Elsewhere, tasks travel in batches: one round trip (and one pickled copy of what
        # the tasks share, such as the run's configuration) per batch, not per task.
        if batches is not None and batches < 1:
            raise ValueError(f"batches must be >= 1, got {batches}")
        cut = _batches(items, batches or self.BATCHES_PER_SLOT * self._slots())
        if self._client is not None:
            futures = self._client.map(_run_batch, [(fn, b) for b in cut], pure=False)
            return Pending(fn, items, futures, [len(b) for b in cut], self._client)
        if self._pool is None:
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers, mp_context=mp.get_context("spawn"),
                initializer=_init_worker, initargs=(os.getpid(),),
            )
        futures = [self._pool.submit(_run_batch, (fn, b)) for b in cut]
        return Pending(fn, items, futures, [len(b) for b in cut])

    def _slots(self) -> int:
        """How many tasks can run at once where this executor runs them."""
        if self._client is not None:
            threads = sum(self._client.nthreads().values())
            return max(1, int(threads))
        return self.workers

    def close(self) -> None:
        """Stop the local workers and disconnect from the cluster."""
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        if self._client is not None:
            self._client.close()
            self._client = None

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Pending(Generic[R]):
    """The results of one :meth:`Executor.submit`, in task order.

    Made by :meth:`Executor.submit`; in this process, the tasks run in :meth:`result`.
    """

    def __init__(self, fn: Callable[[Any], R], items: Sequence[Any], futures: list[Any],
                 sizes: list[int] | None, client: Any = None) -> None:
        self._fn = fn
        self._items = items
        self._futures = futures
        self._sizes = sizes
        self._client = client  # Dask's, when the futures are Dask's
        self._results: list[R] | None = None
        self._cancelled = False
        #: In this process: the tasks given up (:meth:`drop`), not run.
        self._skip = [False] * len(items)

    def result(self, on_done: Callable[[int], None] | None = None) -> list[R]:
        """Wait for the results (run the tasks, in this process).

        Parameters
        ----------
        on_done : callable, optional
            Called with the number of finished tasks, as in :meth:`Executor.map`.

        Raises
        ------
        Exception
            The first task error, as raised in the task.
        """
        if self._cancelled:
            raise RuntimeError("the results of a cancelled submission were asked for")
        if self._results is not None:
            return self._results
        out: list[Any] = []
        if self._sizes is None:  # in this process
            for i, t in enumerate(self._items):
                out.append(None if self._skip[i] else self._fn(t))
                if on_done:
                    on_done(i + 1)
        elif self._client is not None:
            from dask.distributed import as_completed

            sizes = {f.key: n for f, n in zip(self._futures, self._sizes, strict=True)}
            done = 0
            for f in as_completed(self._futures):
                done += sizes[f.key]
                if on_done:
                    on_done(done)
            for chunk in self._client.gather(self._futures):
                out.extend(chunk)
        else:
            for f, size in zip(self._futures, self._sizes, strict=True):
                out.extend([None] * size if f.cancelled() else f.result())
                if on_done:
                    on_done(len(out))
        self._results = out
        return out

    def drop(self, unwanted: Sequence[bool]) -> int:
        """Give up the tasks flagged in `unwanted` (one flag per task, in order) where it
        saves work: on local worker processes, a batch not started yet whose every task is
        unwanted does not run; in this process, an unwanted task is not run. :meth:`result`
        gives None in place of the results not computed (an unwanted task's result may
        still come: its batch had started, or held a wanted task). On Dask nothing is
        given up.

        Returns
        -------
        int
            The tasks given up.
        """
        flags = [bool(u) for u in unwanted]
        if len(flags) != len(self._items):
            raise ValueError(f"drop: {len(flags)} flags for {len(self._items)} tasks")
        if self._results is not None or self._cancelled or self._client is not None:
            return 0
        if self._sizes is None:
            self._skip = [a or b for a, b in zip(self._skip, flags, strict=True)]
            return sum(self._skip)
        given_up, i = 0, 0
        for f, size in zip(self._futures, self._sizes, strict=True):
            if all(flags[i:i + size]) and not f.cancelled() and f.cancel():
                given_up += size
            i += size
        return given_up

    def cancel(self) -> None:
        """Drop the results: batches not started yet do not run (those running finish)."""
        for f in self._futures:
            f.cancel()
        self._futures = []
        self._cancelled = True


def _batches(items: Sequence[T], n: int) -> list[list[T]]:
    """`items` cut into at most `n` contiguous batches of near-equal size, in order."""
    n = max(1, min(n, len(items)))
    size, extra = divmod(len(items), n)
    out, i = [], 0
    for k in range(n):
        j = i + size + (1 if k < extra else 0)
        out.append(list(items[i:j]))
        i = j
    return out


def _run_batch(job: tuple[Callable[[T], R], Sequence[T]]) -> list[R]:
    """Run one batch in a worker: ``[fn(t) for t in batch]``."""
    fn, batch = job
    return [fn(t) for t in batch]


#: How often (s) a local worker checks that the process that started it is alive.
PARENT_POLL_S = 1.0


def _init_worker(parent: int) -> None:
    """Set up a local worker: one BLAS thread (the workers are the parallelism), and a
    watch on its parent, the process `parent`: killed (SIGKILL, a closed terminal), the
    parent cannot stop its workers, and one in the middle of a long batch would run on,
    orphaned, for minutes. (The pid is passed, not read here: the parent may be gone
    before a worker has started.)"""
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="a2l-parent-watch", daemon=True).start()

