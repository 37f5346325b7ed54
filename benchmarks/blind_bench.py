"""Blind-prompt benchmark of L0 (and L1's mass): prompts written by someone who never saw the lexicon, each through
L0 at draft, its three renders saved for a blind judge, and the mass L1 would give it (l1_plan: density prior x
built volume) against the prompt's sourced real mass.

    python -m benchmarks.blind_bench tests/geometry/blind_prompts.jsonl --out docs/blind/set1 [--json] [--limit N]

Writes OUT/views/<id>.png (iso | front | side; iso | top | front for a flat object: views.telling_views),
OUT/judge.jsonl (id, prompt, image: what a judge sees), OUT/table.json (every figure) and OUT/contact_sheet.png;
prints the table (or JSON with --json). L0 seconds are the CPU seconds of L0's units (mesh, proxy, particles,
Gaussians, checks), comparable on a shared machine; run it under `taskset -c 0` for the one-core figure."""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import imageio.v3 as iio
import numpy as np

from contracts.errors import InputError
from contracts.request import AssetRequest
from tasks.physical.plan import l1_plan
from tasks.agents.intent import targets_from_request
from tasks.geometry import pipeline, sources
from tasks.geometry.outputs import load_l0, write_outputs
from tasks.render.views import telling_views
from benchmarks.geometry_bench import contact_sheet



def load_jsonl(path: Path) -> list[dict]:
    """Prompt lines {id, text, object, mass_kg, mass_source, size_m}."""
    rows = [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]
    bad = [r.get("id") for r in rows if not str(r.get("text", "")).strip()]
    if bad or not rows:
        raise InputError(f"{path}: prompts {bad or '[]'} have no text")
    return rows


def bench_one(prompt: dict, settings: pipeline.L0Settings, out: Path) -> dict:
    """One prompt: L0's units timed, outputs written to a temp folder, L1's mass plan, the three views kept."""
    done = out / "rows" / f"{prompt['id']}.json"
    if done.is_file():  # a killed run resumes: finished prompts are kept
        return json.loads(done.read_text(encoding="utf-8"))
    row = _bench_one(prompt, settings, out)
    done.parent.mkdir(parents=True, exist_ok=True)
    done.write_text(json.dumps(row), encoding="utf-8")
    return row


def _bench_one(prompt: dict, settings: pipeline.L0Settings, out: Path) -> dict:
    t0, c0 = time.perf_counter(), time.process_time()
    request = AssetRequest(text=prompt["text"])
    try:
        targets_from_request(request)  # what the CLI refuses before any layer (a rigid material or object)
        mesh, info = sources.build_mesh(request, settings)
        proxy = pipeline.build_proxy(mesh, settings.coacd)
        particles = pipeline.build_particles(mesh, settings.particles)
        gaussians = pipeline.build_gaussians(mesh, particles, settings)
        checks = pipeline.check_geometry(mesh, proxy, particles, gaussians)
    except InputError as exc:
        return {"id": prompt["id"], "text": prompt["text"], "object": prompt.get("object"), "error": str(exc),
                "expected_mass_kg": prompt.get("mass_kg")}
    except Exception as exc:  # a bug, not a refusal: recorded as a failed prompt (not built), the run goes on
        return {"id": prompt["id"], "text": prompt["text"], "object": prompt.get("object"), "crashed": True,
                "error": f"internal error ({type(exc).__name__}): {exc}", "expected_mass_kg": prompt.get("mass_kg")}
    seconds, cpu_seconds = time.perf_counter() - t0, time.process_time() - c0
    with tempfile.TemporaryDirectory(prefix="ds-blind-") as tmp:
        folder = Path(tmp) / "l0"
        write_outputs(folder, mesh, proxy, particles, gaussians, info, checks, extra={"request": request.model_dump(
            mode="json")})
        asset = load_l0(folder)
        plan = l1_plan(asset, None)
        volume = float(np.sum(asset.volumes_m3))
        mass = plan.mass.density_kg_per_m3 * volume
        views = [iio.imread(folder / "renders" / f"{v}.png")[..., :3] for v in telling_views(asset.mesh.extents)]
    strip = np.concatenate(views, axis=1)
    (out / "views").mkdir(parents=True, exist_ok=True)
    iio.imwrite(out / "views" / f"{prompt['id']}.png", strip)
    c = info.concept
    row = {"id": prompt["id"], "text": prompt["text"], "object": prompt.get("object"), "concept": info.entry,
           "fallback_level": c.fallback_level if c else None,
           "analogy": c.analogy_line() if c is not None else None, "material": plan.material,
           "extents_m": [round(float(v), 4) for v in asset.mesh.extents], "mass_kg": round(mass, 4),
           "gates_passed": checks.passed, "seconds": round(seconds, 2), "cpu_seconds": round(cpu_seconds, 2)}
    if prompt.get("mass_kg"):
        row["expected_mass_kg"] = float(prompt["mass_kg"])
        row["mass_ratio"] = round(mass / float(prompt["mass_kg"]), 3)
    return row


def _shown(path: Path) -> str:
    """The prompts file as the table records it: relative to the working directory when under it (no machine path)."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def run(path: Path, out: Path, quality: str = "draft", limit: int | None = None, progress=print) -> dict:  # noqa: ANN001
    """Every prompt of a JSONL file; the table, the judge's file and the contact sheet under out."""
    prompts = load_jsonl(path)[:limit]
    settings = pipeline.settings_from_contract(quality)  # type: ignore[arg-type]
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for i, p in enumerate(prompts):
        progress(f"[{i + 1}/{len(prompts)}] {p['text']}")
        rows.append(bench_one(p, settings, out))
    with (out / "judge.jsonl").open("w", encoding="utf-8") as fh:
        for r in rows:
            if "error" not in r:
                fh.write(json.dumps({"id": r["id"], "prompt": r["text"], "image": f"views/{r['id']}.png"}) + "\n")
    ok = [r for r in rows if "error" not in r]
    if ok:
        images = [iio.imread(out / "views" / f"{r['id']}.png")[::3, ::3] for r in ok]
        labels = [f"{r['id']} {r['text']}" for r in ok]
        iio.imwrite(out / "contact_sheet.png", contact_sheet(images, labels, columns=5))
    with_m = [r for r in ok if "mass_ratio" in r]
    summary = {"prompts": len(rows), "errors": len(rows) - len(ok),
               "by_analogy": sum(r["fallback_level"] not in ("exact", "synonym") for r in ok),
               "mass_within_2x_fraction": (sum(0.5 <= r["mass_ratio"] <= 2.0 for r in with_m) / len(with_m)
                                           if with_m else None),
               "max_cpu_seconds": max((r["cpu_seconds"] for r in ok), default=None),
               "mean_cpu_seconds": round(float(np.mean([r["cpu_seconds"] for r in ok])), 2) if ok else None}
    result = {"prompts_file": _shown(path), "quality": quality, "rows": rows, "summary": summary}
    (out / "table.json").write_text(json.dumps(result, indent=2), encoding="utf-8")
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("prompts", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--quality", default="draft")
    ap.add_argument("--limit", type=int)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    result = run(a.prompts, a.out, a.quality, a.limit, progress=lambda m: print(m, file=sys.stderr))
    if a.json:
        print(json.dumps(result, indent=2))
        return 0
    for r in result["rows"]:
        if "error" in r:
            print(f"{r['id']:4s} {r['text'][:50]:50s} error: {r['error']}")
            continue
        ratio = f"{r['mass_ratio']:.2f}" if "mass_ratio" in r else "-"
        print(f"{r['id']:4s} {r['text'][:50]:50s} {r['concept']:24s} {r['fallback_level']:9s} "
              f"{r['mass_kg'] * 1e3:8.1f} g  x{ratio:5s} {r['cpu_seconds']:5.1f} s")
    print(json.dumps(result["summary"]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
