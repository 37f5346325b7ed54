"""Prompt-suite benchmark of L0's text path: per prompt the concept understood, the fallback taken, the size, the
mass estimate and the seconds L0 took; and a contact sheet of the prompts' renders."""

from __future__ import annotations

import json
import time
from pathlib import Path

import cv2
import numpy as np
import yaml

from contracts.errors import InputError
from contracts.request import AssetRequest
from tasks.geometry import pipeline
from tasks.geometry.render import render_view


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
    mesh, info = pipeline.build_mesh(AssetRequest(text=prompt["text"]), settings)
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
