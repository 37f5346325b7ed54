"""MPM tests: quiet Warp, CPU device."""

from __future__ import annotations

import warp as wp

wp.config.quiet = True
