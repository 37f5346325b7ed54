"""Cache benchmark: put/hit latency for a 1M-particle entry and a tiny entry, key computation time, codec choice.

    python -m benchmarks.cache_bench [--cache DIR] [--particles N] [--repeats N] [--compare/--no-compare] [--json]
"""

from __future__ import annotations

import contextlib
import shutil
import statistics
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from pydantic import BaseModel
from rich.table import Table

from cache import store as store_mod
from cache.hashing import content_key
from cache.store import CacheStore
from flows.cli.apps import console, emit_json, fail, results


class _BenchModel(BaseModel):
    """A request-sized pydantic model for key timing."""

    name: str
    young_modulus_pa: float
    poisson_ratio: float
    density_kg_m3: float
    extents_m: list[float]
    tags: dict[str, str]
    seed: int


def particle_state(n: int, seed: int = 0) -> dict[str, np.ndarray]:
    """Positions (N,3), velocities (N,3) and deformation gradients F (N,3,3), float32."""
    rng = np.random.default_rng(seed)
    f = np.broadcast_to(np.eye(3, dtype=np.float32), (n, 3, 3)) + rng.normal(0, 1e-3, (n, 3, 3)).astype(np.float32)
    return {
        "positions": rng.random((n, 3), dtype=np.float32),
        "velocities": rng.normal(0, 0.1, (n, 3)).astype(np.float32),
        "F": np.ascontiguousarray(f),
    }


def _timeit(fn: Callable[[], Any], repeats: int) -> float:
    """Median wall seconds of `repeats` calls."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


@contextlib.contextmanager
def _codec(compressors: Any, chunk_bytes: int) -> Iterator[None]:
    old = (store_mod.COMPRESSORS, store_mod.CHUNK_BYTES)
    store_mod.COMPRESSORS, store_mod.CHUNK_BYTES = compressors, chunk_bytes
    try:
        yield
    finally:
        store_mod.COMPRESSORS, store_mod.CHUNK_BYTES = old


def _put_hit(root: Path, value: Any, repeats: int, tag: str) -> dict[str, float]:
    """Median put (fresh key each time) and hit (verified load) latency."""
    store = CacheStore(root)
    keys = [content_key(tag, i, time.time_ns()) for i in range(repeats)]
    it = iter(keys)
    put_s = _timeit(lambda: store.put(next(it), value), repeats)
    hit_s = _timeit(lambda: store.get(keys[0]), repeats)
    size = sum(p.stat().st_size for p in store.entry_dir(keys[0]).rglob("*") if p.is_file())
    for k in keys:
        store.remove(k)
    return {"put_s": put_s, "hit_s": hit_s, "entry_bytes": int(size)}


def codec_options() -> dict[str, tuple[Any, int]]:
    """Candidate (compressors, chunk bytes) settings compared by the benchmark."""
    from zarr.codecs import BloscCodec, ZstdCodec

    return {
        "none_16MB_chunks": (None, 16 << 20),
        "none_4MB_chunks": (None, 4 << 20),
        "blosc_lz4_shuffle_16MB": (BloscCodec(cname="lz4", clevel=1, shuffle="shuffle"), 16 << 20),
        "zstd1_16MB": (ZstdCodec(level=1), 16 << 20),
    }


def run_bench(root: Path | None = None, n: int = 1_000_000, repeats: int = 3, compare: bool = True) -> dict[str, Any]:
    """Run the benchmark in a temp dir (under `root` when given, to measure that filesystem)."""
    if root is not None:
        root.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="deformsmith-bench-", dir=root))
    try:
        big = particle_state(n)
        tiny = {"mass_kg": 0.12, "ok": True, "extents_m": (0.1, 0.05, 0.02), "note": "tiny"}
        model = _BenchModel(name="sponge", young_modulus_pa=8.0e4, poisson_ratio=0.3, density_kg_m3=300.0,
                            extents_m=[0.1, 0.06, 0.04], tags={"category": "sponge", "source": "bench"}, seed=7)
        out: dict[str, Any] = {
            "particles": n,
            "big_entry_mb": round(sum(a.nbytes for a in big.values()) / 1e6, 3),
            "repeats": repeats,
            "codec": {"compressors": repr(store_mod.COMPRESSORS), "chunk_bytes": store_mod.CHUNK_BYTES},
            "key_1m_arrays_s": _timeit(lambda: content_key("bench", big), repeats),
            "key_model_s": _timeit(lambda: content_key("bench", model), max(repeats, 20)),
            "key_tiny_s": _timeit(lambda: content_key("bench", tiny), max(repeats, 20)),
        }
        res = _put_hit(work / "main", big, repeats, "big")
        out.update({"put_1m_s": res["put_s"], "hit_1m_s": res["hit_s"], "entry_1m_bytes": res["entry_bytes"]})
        res = _put_hit(work / "main", tiny, max(repeats, 10), "tiny")
        out.update({"put_tiny_s": res["put_s"], "hit_tiny_s": res["hit_s"], "entry_tiny_bytes": res["entry_bytes"]})
        if compare:
            out["codecs"] = {}
            for name, (comp, chunk) in codec_options().items():
                with _codec(comp, chunk):
                    out["codecs"][name] = _put_hit(work / name, big, repeats, name)
        return out
    finally:
        shutil.rmtree(work, ignore_errors=True)


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)
JsonOption = Annotated[bool, typer.Option("--json", help="Print machine-readable JSON on stdout.")]


@app.command()
def bench_cache_cmd(
    cache: Annotated[Path | None, typer.Option("--cache", help="Benchmark on this filesystem (a temp dir under it; default: system temp).")] = None,
    particles: Annotated[int, typer.Option("--particles", min=1, help="Particles in the large entry.")] = 1_000_000,
    repeats: Annotated[int, typer.Option("--repeats", min=1, help="Repetitions per figure (median reported).")] = 3,
    compare: Annotated[bool, typer.Option("--compare/--no-compare", help="Also compare Zarr codec/chunk settings.")] = True,
    json_out: JsonOption = False,
) -> None:
    """Put/hit latency of a 1M-particle entry (positions, velocities, F) and a tiny one; key computation time."""
    if cache is not None and cache.exists() and not cache.is_dir():
        fail(f"--cache {cache} is not a directory")
    with console.status("benchmarking the cache ..."):
        data = run_bench(cache.absolute() if cache else None, n=particles, repeats=repeats, compare=compare)
    if json_out:
        emit_json(data)
        return
    table = Table(title=f"cache benchmark ({data['particles']} particles, {data['big_entry_mb']} MB)")
    table.add_column("figure")
    table.add_column("value", justify="right")
    for k, v in data.items():
        if isinstance(v, float):
            table.add_row(k, f"{v * 1e3:.2f} ms" if k.endswith("_s") else f"{v:g}")
    for name, res in data.get("codecs", {}).items():
        table.add_row(f"codec {name}", f"put {res['put_s'] * 1e3:.1f} ms / hit {res['hit_s'] * 1e3:.1f} ms")
    results.print(table)


if __name__ == "__main__":
    app()
