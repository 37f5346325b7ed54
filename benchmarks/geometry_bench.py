"""L0's benchmark: wall time, peak memory and CoACD share for the plush turtle per quality and the largest
pybullet_data mesh (each case in a fresh process); with --suite, the prompt-suite benchmark of L0's text path: per
prompt the concept understood, the fallback taken, the size, the mass estimate and the seconds L0 took; and a contact
sheet of the prompts' renders.

    python -m benchmarks.geometry_bench [--qualities draft,standard,high] [--skip-cache] [--json]
    python -m benchmarks.geometry_bench --suite tests/geometry/heldout_prompts.yaml [--contact-sheet sheet.png] [--json]
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np
import typer
import yaml

from contracts.errors import InputError
from contracts.request import AssetRequest
from flows.cli.apps import console, emit_json, fail, results
from flows.cli.geometry_cmds import QUALITIES
from tasks.geometry import pipeline, sources
from tasks.render.views import render_view


def load_prompts(path: Path) -> list[dict]:
    """Prompts of a suite file (YAML or JSON): `prompts: [{text, concept?, mass_kg?}]` (tests/geometry/
    heldout_prompts.yaml) or an evaluation suite's `cases` (its text cases)."""
    if not path.is_file():
        raise InputError(f"suite file not found: {path}")
    try:
        raw = yaml.safe_load(path.read_text(encoding="utf-8"))
    except yaml.YAMLError as exc:
        raise InputError(f"suite file {path} is not YAML/JSON: {exc}") from exc
    if isinstance(raw, dict) and isinstance(raw.get("prompts"), list):
        prompts = raw["prompts"]
    elif isinstance(raw, dict) and isinstance(raw.get("cases"), list):
        prompts = [{"text": c["text"], "id": c.get("id")} for c in raw["cases"] if c.get("kind") == "text"]
    else:
        raise InputError(f"suite file {path} has neither 'prompts' nor 'cases' (a list)")
    bad = [i for i, p in enumerate(prompts) if not isinstance(p, dict) or not str(p.get("text", "")).strip()]
    if bad or not prompts:
        raise InputError(f"suite file {path}: prompts {bad or '[]'} have no text")
    return prompts


def bench_prompt(prompt: dict, settings: pipeline.L0Settings) -> tuple[dict, np.ndarray]:
    """One prompt through every L0 unit: the figures (wall and CPU seconds: on a shared machine the CPU time is the
    comparable one) and a side-view render (RGB uint8)."""
    t0, c0 = time.perf_counter(), time.process_time()
    mesh, info = sources.build_mesh(AssetRequest(text=prompt["text"]), settings)
    proxy = pipeline.build_proxy(mesh, settings.coacd)
    particles = pipeline.build_particles(mesh, settings.particles)
    gaussians = pipeline.build_gaussians(mesh, particles, settings)
    checks = pipeline.check_geometry(mesh, proxy, particles, gaussians)
    seconds, cpu_seconds = time.perf_counter() - t0, time.process_time() - c0
    m = pipeline.arrays_to_mesh(mesh)
    c = info.concept
    mass = c.mass_estimate_kg(float(m.volume), float(m.area)) if c is not None else None
    row = {
        "text": prompt["text"], "concept": info.entry, "fallback_level": c.fallback_level if c else None,
        "fallback_note": c.fallback_note if c else None, "shape_from": c.shape_from if c else None,
        "extents_m": [round(float(v), 4) for v in m.extents], "mass_estimate_kg": mass,
        "typical_mass_range_kg": list(c.typical_mass_range_kg) if c and c.typical_mass_range_kg else None,
        "seconds": round(seconds, 2), "cpu_seconds": round(cpu_seconds, 2), "gates_passed": checks.passed,
        "failed_gates": checks.failed,
    }
    if "concept" in prompt:
        row["expected_concept"] = prompt["concept"]
        row["concept_ok"] = info.entry == prompt["concept"]
    if "mass_kg" in prompt and mass is not None:
        row["expected_mass_kg"] = prompt["mass_kg"]
        row["mass_ratio"] = round(mass / float(prompt["mass_kg"]), 3)
    flat = m.extents[2] < 0.35 * max(m.extents[0], m.extents[1])
    return row, render_view(m, "top" if flat else "side", 192)


def summary(rows: list[dict]) -> dict:
    """Shares of prompts with the expected concept and with a mass within 2x; the slowest prompt [s]."""
    with_c = [r for r in rows if "concept_ok" in r]
    with_m = [r for r in rows if "mass_ratio" in r]
    return {
        "prompts": len(rows),
        "concept_ok_fraction": sum(r["concept_ok"] for r in with_c) / len(with_c) if with_c else None,
        "mass_within_2x_fraction": sum(0.5 <= r["mass_ratio"] <= 2.0 for r in with_m) / len(with_m) if with_m else None,
        "gates_passed_fraction": sum(r["gates_passed"] for r in rows) / len(rows),
        "max_seconds": max(r["seconds"] for r in rows), "mean_seconds": float(np.mean([r["seconds"] for r in rows])),
        "max_cpu_seconds": max(r["cpu_seconds"] for r in rows),
    }


def contact_sheet(images: list[np.ndarray], labels: list[str], columns: int = 6) -> np.ndarray:
    """Tiles of renders with a two-line label under each (RGB uint8)."""
    h, w = images[0].shape[:2]
    lab = 34
    rows = -(-len(images) // columns)
    sheet = np.full((rows * (h + lab), columns * w, 3), 255, np.uint8)
    for i, (img, text) in enumerate(zip(images, labels)):
        r, c = divmod(i, columns)
        y, x = r * (h + lab), c * w
        sheet[y : y + h, x : x + w] = img
        line1, line2 = (text[:30], text[30:60]) if len(text) > 30 else (text, "")
        for j, line in enumerate((line1, line2)):
            cv2.putText(sheet, line, (x + 4, y + h + 13 + 14 * j), cv2.FONT_HERSHEY_SIMPLEX, 0.36, (20, 20, 20), 1,
                        cv2.LINE_AA)
    return sheet


def run_suite(path: Path, quality: str, sheet_path: Path | None = None, progress=None) -> dict:  # noqa: ANN001
    """Every prompt of a suite: rows, summary and (optionally) the contact sheet written to sheet_path."""
    prompts = load_prompts(path)
    settings = pipeline.settings_from_contract(quality)  # type: ignore[arg-type]
    rows, images = [], []
    for i, p in enumerate(prompts):
        if progress:
            progress(f"[{i + 1}/{len(prompts)}] {p['text']}")
        row, img = bench_prompt(p, settings)
        rows.append(row)
        images.append(img)
    if sheet_path is not None:
        import imageio.v3 as iio

        labels = [f"{r['text']} -> {r['concept']}" for r in rows]
        sheet_path.parent.mkdir(parents=True, exist_ok=True)
        tmp = sheet_path.with_name(sheet_path.name + ".tmp.png")
        iio.imwrite(tmp, contact_sheet(images, labels))
        tmp.replace(sheet_path)
    return {"suite": str(path), "quality": quality, "rows": rows, "summary": summary(rows)}


def dumps(result: dict) -> str:
    """JSON of a suite result."""
    return json.dumps(result, indent=2)


app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)

_BENCH_CASE = r"""
import json, resource, sys, time
from contracts.request import AssetRequest
from tasks.geometry import pipeline, sources
req = AssetRequest(**json.loads(sys.argv[1]))
s = pipeline.settings_from_contract(sys.argv[2], seed=0)
t = {}
t0 = time.perf_counter(); mesh, info = sources.build_mesh(req, s); t["mesh_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); proxy = pipeline.build_proxy(mesh, s.coacd); t["coacd_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); parts = pipeline.build_particles(mesh, s.particles); t["particles_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); g = pipeline.build_gaussians(mesh, parts, s); t["gaussians_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); ch = pipeline.check_geometry(mesh, proxy, parts, g); t["checks_s"] = time.perf_counter() - t0
import tempfile, pathlib
from tasks.geometry.outputs import write_outputs
with tempfile.TemporaryDirectory() as d:
    t0 = time.perf_counter(); write_outputs(pathlib.Path(d), mesh, proxy, parts, g, info, ch); t["write_s"] = time.perf_counter() - t0
t["total_s"] = sum(t.values())
t["coacd_fraction"] = t["coacd_s"] / t["total_s"]
t["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
t.update(particles=len(parts["positions_m"]), gaussians=len(g["positions_m"]), faces=len(mesh["faces"]),
         convex_parts=len(proxy["part_face_count"]), gates_passed=ch.passed)
print(json.dumps(t))
"""

_BENCH_CACHE = r"""
import json, sys, time
from contracts.request import AssetRequest
from flows.l0_geometry import run_l0
req = AssetRequest(**json.loads(sys.argv[1]))
t0 = time.perf_counter(); run_l0(req, "draft"); first = time.perf_counter() - t0
t0 = time.perf_counter(); run_l0(req, "draft"); second = time.perf_counter() - t0
print(json.dumps({"first_run_s": first, "cache_hit_rerun_s": second}))
"""


def _run_case(code: str, *args: str, env: dict[str, str] | None = None) -> dict:
    proc = subprocess.run([sys.executable, "-P", "-c", code, *args], capture_output=True, text=True,
                          env={**os.environ, **(env or {})})
    if proc.returncode != 0:
        fail(f"benchmark case failed: {proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else proc.returncode}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _bench_suite(suite: Path, quality: str, sheet: Path | None, as_json: bool) -> None:
    """`--suite`: every prompt through L0, one row each (run_suite above)."""
    quality = quality.split(",")[0]
    if quality not in QUALITIES:
        fail(f"--qualities must name one of {', '.join(QUALITIES)}, not '{quality}'")
    try:
        result = run_suite(suite, quality, sheet, progress=lambda m: console.print(m))
    except InputError as exc:
        fail(str(exc))
    if as_json:
        emit_json(result)
        return
    for r in result["rows"]:
        mass = f"{r['mass_estimate_kg'] * 1e3:8.1f} g" if r["mass_estimate_kg"] is not None else "       -  "
        ext = " x ".join(f"{v:.3f}" for v in r["extents_m"])
        results.print(f"{r['text'][:44]:44s} {r['concept']:20s} {r['fallback_level']:9s} {ext} m {mass} "
                      f"{r['seconds']:5.1f} s")
    results.print(result["summary"])


@app.command()
def bench_geometry(
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
    skip_cache: bool = typer.Option(False, "--skip-cache", help="skip the cache-hit measurement (Prefect start-up)"),
    qualities: str = typer.Option(",".join(QUALITIES), "--qualities", help="comma-separated qualities"),
    suite: Path = typer.Option(None, "--suite", help="YAML/JSON prompt suite (e.g. tests/geometry/heldout_prompts.yaml "
                               "or contracts/suites/default.yaml): per prompt the concept, fallback level, size, "
                               "mass estimate and seconds of L0 (at the first of --qualities, default draft)"),
    contact_sheet: Path = typer.Option(None, "--contact-sheet", help="with --suite: PNG of every prompt's render"),
) -> None:
    """L0 wall time, peak memory and CoACD share for the plush turtle per quality and the largest pybullet_data mesh;
    with --suite, the text path on every prompt of a suite."""
    if suite is not None:
        _bench_suite(suite, qualities if qualities != ",".join(QUALITIES) else "draft", contact_sheet, as_json)
        return
    import pybullet_data

    turtle = json.dumps({"text": "a soft plush turtle toy, about 25 cm long"})
    data = Path(pybullet_data.getDataPath())
    candidates = [data / n for n in ("duck.obj", "teddy2_VHACD_CHs.obj", "bunny.obj", "torus/torus_textured.obj",
                                     "soccerball.obj")]
    largest = max(candidates, key=lambda p: p.stat().st_size)
    mesh_req = json.dumps({"mesh_path": str(largest), "size_hint_m": 0.2})
    figures: dict = {"turtle": {}, "largest_pybullet_mesh": {"file": largest.name}}
    for q in qualities.split(","):
        console.print(f"turtle, {q} ...")
        figures["turtle"][q] = _run_case(_BENCH_CASE, turtle, q)
        console.print(f"{largest.name}, {q} ...")
        figures["largest_pybullet_mesh"][q] = _run_case(_BENCH_CASE, mesh_req, q)
    if not skip_cache:
        console.print("cache-hit rerun (Prefect flow, fresh cache) ...")
        with tempfile.TemporaryDirectory() as d:
            figures["turtle"]["cache"] = _run_case(_BENCH_CACHE, turtle, env={"DEFORMSMITH_CACHE": d,
                                                                                "PREFECT_LOGGING_LEVEL": "WARNING"})
    figures["cpu_count"] = os.cpu_count()
    if as_json:
        emit_json(figures)
        return
    for name in ("turtle", "largest_pybullet_mesh"):
        for q, f in figures[name].items():
            if isinstance(f, dict) and "total_s" in f:
                results.print(f"{name:24s} {q:9s} total {f['total_s']:6.2f} s  coacd {f['coacd_s']:6.2f} s "
                              f"({100 * f['coacd_fraction']:.0f}%)  peak {f['peak_rss_mb']:.0f} MB  "
                              f"{f['particles']} particles")
    if "cache" in figures["turtle"]:
        c = figures["turtle"]["cache"]
        results.print(f"flow first run {c['first_run_s']:.2f} s, cache-hit rerun {c['cache_hit_rerun_s']:.2f} s")


if __name__ == "__main__":
    app()
