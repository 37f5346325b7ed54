"""L2 tests: quiet Warp on the CPU."""

from __future__ import annotations

import warp as wp

wp.config.quiet = True
