"""``python -m a2l.cli``: the ``a2l`` command."""

import sys

from a2l.cli import main

sys.exit(main())
