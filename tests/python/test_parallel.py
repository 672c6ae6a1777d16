"""The executor: tasks cut into ordered batches, the same results in this process and on
local worker processes."""

from __future__ import annotations

import math

import pytest

from a2l.parallel import Executor, _batches


@pytest.mark.parametrize(("n_items", "n_batches"), [(10, 3), (3, 8), (1, 1), (64, 8), (7, 7)])
def test_batches_keep_order_and_balance(n_items: int, n_batches: int) -> None:
    items = list(range(n_items))
    out = _batches(items, n_batches)
    assert [x for b in out for x in b] == items
    assert len(out) == min(n_items, n_batches)
    sizes = [len(b) for b in out]
    assert min(sizes) >= 1 and max(sizes) - min(sizes) <= 1


def test_two_workers_give_the_in_process_results_in_order() -> None:
    tasks = [float(i) for i in range(37)]
    seen: list[int] = []
    with Executor(workers=2) as ex:
        out = ex.map(math.sqrt, tasks, on_done=seen.append)
    assert out == [math.sqrt(t) for t in tasks]
    assert seen == sorted(seen) and seen[-1] == len(tasks)
    assert Executor(workers=1).map(math.sqrt, tasks) == out
    # one task per batch (a sweep's seeds): the same results, one progress call per task
    seen.clear()
    with Executor(workers=2) as ex:
        assert ex.map(math.sqrt, tasks, on_done=seen.append, batches=len(tasks)) == out
        with pytest.raises(ValueError, match="batches"):
            ex.submit(math.sqrt, tasks, batches=0)
    assert seen == list(range(1, len(tasks) + 1))


def test_a_task_error_reaches_the_caller() -> None:
    with Executor(workers=2) as ex, pytest.raises(ValueError, match="math domain error"):
        ex.map(math.sqrt, [1.0, -1.0, 4.0])


def test_tasks_given_up_do_not_run_where_not_started() -> None:
    tasks = list(range(-40, 0))
    unwanted = [i >= 10 for i in range(len(tasks))]
    with Executor(workers=2) as ex:
        pending = ex.submit(abs, tasks, batches=len(tasks))
        # the workers are still starting: at most a few batches are running or queued
        given_up = pending.drop(unwanted)
        out = pending.result()
        assert pending.drop(unwanted) == 0  # the results are in: nothing left to give up
    assert out[:10] == [abs(t) for t in tasks[:10]]  # the wanted ones, all computed
    assert all(o is None or o == abs(t) for o, t in zip(out[10:], tasks[10:], strict=True))
    assert given_up == sum(o is None for o in out) >= 20
    # in this process the tasks given up are not run
    pending = Executor(workers=1).submit(abs, tasks)
    assert pending.drop(unwanted) == 30
    assert pending.result() == [abs(t) for t in tasks[:10]] + [None] * 30
    with pytest.raises(ValueError, match="flags"):
        Executor(workers=1).submit(abs, tasks).drop([True])


_PARENT = """
import sys, time
from a2l.parallel import Executor
ex = Executor(workers=2)
pending = ex.submit(time.sleep, [60.0, 60.0])
time.sleep(0.2)
pid = [p.pid for p in ex._pool._processes.values()][0]
print(pid, flush=True)
time.sleep(60)
"""


def test_a_worker_whose_parent_is_killed_exits() -> None:
    """The parent killed outright (SIGKILL) cannot stop its workers: a worker, in the middle
    of a 60 s task, sees that its parent is gone and exits within a few seconds."""
    import os
    import signal
    import subprocess
    import sys
    import time

    parent = subprocess.Popen([sys.executable, "-c", _PARENT], stdout=subprocess.PIPE,
                              text=True)
    try:
        worker = int(parent.stdout.readline())  # type: ignore[union-attr]
        os.kill(worker, 0)  # running
        parent.send_signal(signal.SIGKILL)
        parent.wait(10)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and _alive(worker):
            time.sleep(0.1)
        if not _alive(worker):
            return
        os.kill(worker, signal.SIGKILL)
        pytest.fail("the orphaned worker was still running 10 s after its parent died")
    finally:
        parent.kill()


def _alive(pid: int) -> bool:
    """`pid` runs (a zombie, exited and not yet reaped by its new parent, does not)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False
