"""The content fingerprint of an asset directory: what two runs of one request must both have written, file by file,
whatever the clock and the recording ids said."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from tasks.record import recording_digest


def content_fingerprint(asset_dir: Path) -> dict[str, str]:
    """Relative path -> digest of every file: JSON canonically, `.rrd` by what it shows (Rerun stamps ids and
    wall-clock times on each write), everything else by bytes. Two runs of the same request on CPU match."""
    root = Path(asset_dir)
    out: dict[str, str] = {}
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = path.relative_to(root).as_posix()
        if path.suffix == ".rrd":
            out[rel] = recording_digest(path)
        elif path.suffix == ".json":
            doc = json.dumps(json.loads(path.read_text(encoding="utf-8")), sort_keys=True)
            out[rel] = hashlib.sha256(doc.encode()).hexdigest()
        elif path.suffix == ".jsonl":
            text = path.read_text(encoding="utf-8")
            lines = [json.dumps(json.loads(ln), sort_keys=True) for ln in text.splitlines() if ln.strip()]
            out[rel] = hashlib.sha256("\n".join(lines).encode()).hexdigest()
        else:
            out[rel] = hashlib.sha256(path.read_bytes()).hexdigest()
    return out
