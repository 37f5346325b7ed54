"""Suite files: load, validate, draw image cases, turn cases into AssetRequests.

Format (YAML or JSON; ``contracts.evaluation.Suite``)::

    name: my-suite                 # required
    version: 1
    description: free text
    manipulation_conditions:       # held-out conditions of ablation C: target (x, y) [m], initial yaw [deg]
      - {target_xy_m: [0.06, -0.08], initial_yaw_deg: 30}
    cases:                         # required, ids unique, slug [a-z0-9_-]
      - {id: t01, kind: text, text: "a soft plush turtle toy, about 25 cm long", intent: "soft plush",
         expected_material: plush, size_m: 0.25, manipulation: false, tags: [plush]}
      - {id: i01, kind: image, image: photos/ball.png, size_m: 0.08, intent: "soft foam"}       # a file, or ...
      - {id: i02, kind: image, drawing: {shape: ellipse, color: [230, 120, 30], aspect: 0.8},    # ... a drawing
         size_m: 0.08, intent: "soft foam"}
      - {id: m01, kind: mesh, mesh: "pybullet_data:duck.obj", size_m: 0.10, intent: "rubber duck"}

``intent`` is the expected material intent (vocabulary words, contracts/vocab/materials.yaml); ``expected_material``
(optional) is the vocabulary material that intent must name, checked on load. Paths are relative to the suite file;
``pybullet_data:`` paths resolve inside the installed pybullet_data. A JSON-lines file (one case per line) is a suite
named after the file. ``--suite NAME`` finds ``contracts/suites/NAME.yaml``.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import yaml
from pydantic import ValidationError

import contracts

from contracts.errors import InputError, validation_message
from contracts.evaluation import Drawing, Suite, SuiteCase
from contracts.request import AssetRequest, Quality
from tasks.agents.intent import match_material
from tasks.agents.vocab import load_material_vocab

SUITES_DIR = Path(contracts.__file__).resolve().parent / "suites"


def suite_path(name_or_file: str) -> Path:
    """A suite file from a path or a packaged suite name."""
    p = Path(name_or_file).expanduser()
    if p.is_file():
        return p.absolute()
    for ext in (".yaml", ".yml", ".json", ".jsonl"):
        cand = SUITES_DIR / f"{name_or_file}{ext}"
        if cand.is_file():
            return cand
    names = sorted(f.stem for f in SUITES_DIR.glob("*.y*ml"))
    raise InputError(f"suite '{name_or_file}' not found: give a file or one of {', '.join(names) or 'none'}")


def _read(path: Path) -> dict:
    """The suite mapping of a YAML / JSON / JSONL file."""
    text = path.read_text(encoding="utf-8")
    try:
        if path.suffix == ".jsonl":
            cases = [json.loads(ln) for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
            return {"name": path.stem, "cases": cases}
        data = json.loads(text) if path.suffix == ".json" else yaml.safe_load(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        raise InputError(f"{path}: not valid {path.suffix.lstrip('.').upper()}: {exc}") from exc
    if not isinstance(data, dict):
        raise InputError(f"{path}: a suite must be a mapping with 'name' and 'cases'")
    return data


def load_suite(name_or_file: str, check_vocab: bool = True) -> tuple[Suite, Path]:
    """Load and validate a suite; returns (suite, its file). Errors name the file and the field."""
    path = suite_path(name_or_file)
    try:
        suite = Suite.model_validate(_read(path))
    except ValidationError as exc:
        raise InputError(f"{path}: invalid suite: " + validation_message(exc)) from exc
    if check_vocab:
        problems = check_cases(suite, path.parent)
        if problems:
            raise InputError(f"{path}: invalid suite: " + "; ".join(problems))
    return suite, path


def check_cases(suite: Suite, base: Path) -> list[str]:
    """Problems a schema cannot see: unknown materials, intents naming another material, missing files."""
    vocab = load_material_vocab()
    out = []
    for c in suite.cases:
        if c.expected_material is not None:
            if c.expected_material not in vocab.materials:
                out.append(f"{c.id}: expected_material '{c.expected_material}' is not a vocabulary material")
            elif (got := match_material(c.intent, vocab)) != c.expected_material:
                out.append(f"{c.id}: intent '{c.intent}' names '{got}', not '{c.expected_material}'")
        for ref in (c.mesh, c.image):
            if ref is not None and not resolve_path(ref, base).is_file():
                out.append(f"{c.id}: file not found: {ref}")
    return out


def resolve_path(ref: str, base: Path) -> Path:
    """'pybullet_data:<rel>' inside pybullet_data, else a path relative to the suite's folder."""
    if ref.startswith("pybullet_data:"):
        import pybullet_data

        return Path(pybullet_data.getDataPath()) / ref.split(":", 1)[1]
    p = Path(ref).expanduser()
    return p if p.is_absolute() else (base / p)


def draw(drawing: Drawing) -> np.ndarray:
    """RGB uint8 image of a drawing: a shaded filled shape on a light grey background (deterministic)."""
    import cv2

    n = drawing.size_px
    img = np.full((n, n, 3), 235, np.uint8)
    mask = np.zeros((n, n), np.uint8)
    margin = 0.12 * n
    w = n - 2 * margin
    h = w * drawing.aspect
    cx, cy = n / 2, n / 2
    if drawing.shape == "ellipse":
        cv2.ellipse(mask, (int(cx), int(cy)), (int(w / 2), int(h / 2)), 0, 0, 360, 255, -1, cv2.LINE_AA)
    elif drawing.shape == "rounded_rect":
        r = int(drawing.corner * min(w, h))
        x0, y0, x1, y1 = int(cx - w / 2), int(cy - h / 2), int(cx + w / 2), int(cy + h / 2)
        cv2.rectangle(mask, (x0 + r, y0), (x1 - r, y1), 255, -1)
        cv2.rectangle(mask, (x0, y0 + r), (x1, y1 - r), 255, -1)
        for px, py in ((x0 + r, y0 + r), (x1 - r, y0 + r), (x0 + r, y1 - r), (x1 - r, y1 - r)):
            cv2.circle(mask, (px, py), r, 255, -1, cv2.LINE_AA)
    else:
        pts = np.array([[margin + x * w, margin + y * w] for x, y in drawing.points], np.int32)
        cv2.fillPoly(mask, [pts], 255, cv2.LINE_AA)
    yy, xx = np.mgrid[0:n, 0:n].astype(np.float64)
    shade = 1.0 - 0.35 * np.clip(((xx - 0.4 * n) ** 2 + (yy - 0.35 * n) ** 2) ** 0.5 / n, 0, 1)
    color = np.clip(np.asarray(drawing.color, np.float64)[None, None, :] * shade[..., None], 0, 255)
    a = (mask.astype(np.float64) / 255.0)[..., None]
    return (a * color + (1 - a) * img).astype(np.uint8)


def image_file(case: SuiteCase, base: Path, folder: Path) -> Path:
    """The case's image: its file, or its drawing written once (content-named PNG) into folder."""
    if case.image is not None:
        return resolve_path(case.image, base)
    assert case.drawing is not None
    digest = hashlib.sha256(case.drawing.canonical_json().encode()).hexdigest()[:16]
    path = folder / f"{case.id}-{digest}.png"
    if not path.is_file():
        import cv2

        folder.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp.png")
        cv2.imwrite(str(tmp), cv2.cvtColor(draw(case.drawing), cv2.COLOR_RGB2BGR))
        tmp.replace(path)
    return path


def to_request(case: SuiteCase, base: Path, image_folder: Path, quality: Quality = "draft") -> AssetRequest:
    """The AssetRequest of a case (material intent = the case's expected intent)."""
    image = image_file(case, base, image_folder) if case.kind == "image" else None
    mesh = resolve_path(case.mesh, base) if case.kind == "mesh" and case.mesh else None
    return AssetRequest(text=case.text if case.kind == "text" else None, image_path=image, mesh_path=mesh,
                        size_hint_m=case.size_m, material_intent=case.intent, quality=quality)


def select(suite: Suite, limit: int | None = None, ids: list[str] | None = None,
           manipulation: bool = False) -> list[SuiteCase]:
    """The cases to run: given ids (in suite order), else the suite, restricted to ablation C's assets if asked;
    then the first `limit` of them."""
    cases = list(suite.cases)
    if ids:
        unknown = sorted(set(ids) - {c.id for c in cases})
        if unknown:
            raise InputError(f"unknown case ids: {unknown}")
        cases = [c for c in cases if c.id in ids]
    if manipulation:
        cases = [c for c in cases if c.manipulation]
    return cases[:limit] if limit is not None else cases
