"""L2 tests: quiet Warp on the CPU."""

from __future__ import annotations

import warp as wp

wp.config.log_level = wp.LOG_WARNING  # no module-load lines (as tasks.mpm's import sets it)
