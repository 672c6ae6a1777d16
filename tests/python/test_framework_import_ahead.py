"""With worker processes the framework imports the skill-learning pipeline in the background
while the workers babble; in this process it does not (the import would slow the rollouts)."""

from __future__ import annotations

import subprocess
import sys

CHECK = """
import sys
from a2l.framework.loop import import_learning_ahead
from a2l.parallel import Executor
assert "a2l.skills.pipeline" not in sys.modules
assert import_learning_ahead(Executor(workers=1)) is None
assert "a2l.skills.pipeline" not in sys.modules
thread = import_learning_ahead(Executor(workers=2))  # no task submitted: no worker started
thread.join(timeout=120)
assert not thread.is_alive() and "a2l.skills.pipeline" in sys.modules
"""


def test_imported_in_the_background_only_with_workers() -> None:
    # a fresh process: in this one, other tests may have imported the pipeline already
    subprocess.run([sys.executable, "-c", CHECK], check=True, timeout=180)
