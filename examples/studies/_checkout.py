"""Puts this checkout first on ``sys.path``: the study scripts then run the worktree's ``dem_core`` and
``comparisons``, not a copy installed elsewhere (a script's own folder, not the current one, starts the path)."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path[:1]:
    sys.path.insert(0, str(ROOT))
