"""``python -m compas_ccu.cli``: the ``ccu`` command."""

from __future__ import annotations

import sys

from compas_ccu.cli import main

sys.exit(main())
