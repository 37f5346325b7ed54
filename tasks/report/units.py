"""Durations and sizes as the command line reads and writes them: '12h' or '500MB' in, '1.5 MB' and a local time
out."""

from __future__ import annotations

import re
import time

from contracts.errors import InputError

_DURATION = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([smhdw]?)\s*$", re.IGNORECASE)
_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kmgt]?i?b?)\s*$", re.IGNORECASE)
_SECONDS = {"": 1, "s": 1, "m": 60, "h": 3600, "d": 86400, "w": 604800}


def parse_duration(text: str) -> float:
    """'90', '90s', '30m', '12h', '7d', '2w' -> seconds."""
    m = _DURATION.match(text)
    if not m:
        raise InputError(f"invalid duration {text!r} (examples: 3600, 30m, 12h, 7d)")
    return float(m.group(1)) * _SECONDS[m.group(2).lower()]


def parse_size(text: str) -> int:
    """'1000', '500MB', '2G', '1.5GiB' -> bytes (K/M/G/T are powers of 1024)."""
    m = _SIZE.match(text)
    if not m:
        raise InputError(f"invalid size {text!r} (examples: 1000000, 500MB, 2GB)")
    unit = m.group(2).lower()[:1]
    return int(float(m.group(1)) * 1024 ** "bkmgt".index(unit or "b"))


def human_bytes(n: float) -> str:
    """A size for people: '512 B', '1.5 KB' ... '2.0 TB' (powers of 1024)."""
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if abs(n) < 1024 or unit == "TB":
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n} B"


def local_time(ts: float | None) -> str:
    """A Unix time as 'YYYY-mm-dd HH:MM:SS' local time, '-' for none."""
    return "-" if ts is None else time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(ts))
