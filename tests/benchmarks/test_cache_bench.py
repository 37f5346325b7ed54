"""`python -m benchmarks.cache_bench`: cache put/hit and key latency (was cache/bench.py and `deformsmith bench cache`)."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

from benchmarks.cache_bench import app


def test_bench_cache_json(tmp_path: Path) -> None:
    res = CliRunner().invoke(app, ["--particles", "20000", "--repeats", "1", "--no-compare", "--json",
                                   "--cache", str(tmp_path)])
    code, out = res.exit_code, res.stdout
    data = json.loads(out)
    assert code == 0 and data["particles"] == 20000
    for k in ("put_1m_s", "hit_1m_s", "put_tiny_s", "hit_tiny_s", "key_1m_arrays_s", "key_model_s"):
        assert data[k] > 0
    assert list(tmp_path.iterdir()) == []  # the benchmark cleans up after itself
