# PYTHON_ARGCOMPLETE_OK  (argcomplete's global completion of ``python -m compas_ccu.cli``)
"""``python -m compas_ccu.cli``: the ``ccu`` command."""

from __future__ import annotations

import sys

try:
    from compas_ccu.cli import main
except KeyboardInterrupt:  # Ctrl-C while the command is still loading
    print("ccu: interrupted", file=sys.stderr)
    sys.exit(130)

sys.exit(main())
