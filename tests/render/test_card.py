"""The asset card: built from the asset directory's records for an asset with L3 and one without, with the numbers of
material.json / physical.json / manipulation.json, the videos embedded by relative paths; a bad directory is one
`error:` line, exit 2, nothing written."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tasks.render.card import CARD_HTML, CARD_PNG, build_card
from tasks.render.card_data import card_data
from tasks.render.card_text import si

FIXTURES = Path(__file__).parent / "card_fixtures"  # the JSON records of a draft turtle (L3) and a sponge (--no-l3)


def _asset(tmp_path: Path, name: str) -> Path:
    """A copy of a fixture asset's records, with two stills, a short drop video and (turtle) an L3 force record."""
    from tasks.render.protocol_video import card_still_name, write_mp4, write_png

    root = tmp_path / name
    shutil.copytree(FIXTURES / name, root)
    frame = np.full((72, 128, 3), 200, np.uint8)
    frame[30:50, 40:90] = (40, 160, 60)
    write_png(frame, root / "renders" / "front.png")
    write_png(frame, root / "renders" / card_still_name("front", 0.3))
    write_mp4([frame, frame], root / "renders" / "drop_front.mp4", 30.0)
    if (root / "manipulation.json").is_file():
        import zarr

        attempt = json.loads((root / "manipulation.json").read_text())["attempt"]
        g = zarr.open_group(str(root / "interaction" / f"attempt_{attempt:03d}"), mode="w")
        t = np.linspace(0.0, 3.0, 61)
        force = np.zeros((61, 2, 3))
        force[:, 0, 1] = 3.0 * np.sin(np.pi * t / 3.0)  # finger 1 peaks at 3 N
        force[:, 1, 1] = -2.0
        g.create_array("control_t_s", data=t)
        g.create_array("finger_force_n", data=force)
    return root


def test_card_of_an_asset_with_l3_shows_its_numbers_and_their_sources(tmp_path: Path) -> None:
    root = _asset(tmp_path, "turtle")
    png, page = build_card(root)
    assert png == root / CARD_PNG and page == root / CARD_HTML
    from PIL import Image

    assert Image.open(png).size == (1800, 1300)
    html = page.read_text(encoding="utf-8")
    material = json.loads((root / "material.json").read_text())
    physical = json.loads((root / "physical.json").read_text())
    manipulation = json.loads((root / "manipulation.json").read_text())
    for key, unit in (("youngs_modulus_pa", "Pa"), ("damping_rate_per_s", "1/s")):
        assert si(material["material"][key], unit) in html
    for band in material["targets"]["bands"]:  # each band's measured value (or 'not measured'), as on the card
        assert si(material["metrics"].get(band["metric"]), band["unit"]) in html
    assert si(physical["metrics"]["mass_kg"], "kg") in html
    assert si(physical["metrics"]["slide_critical_angle_deg"], "deg") in html
    assert manipulation["plan"]["gripper"] in html
    assert si(manipulation["labels"]["max_finger_force_n"], "N") in html
    best = json.loads((root / "asset.json").read_text())["provenance"]["cache_keys"]["l2.selection.4"]
    assert best[:12] in html  # specimen_compress's probe: the key behind the effective modulus
    assert '<video controls muted loop playsinline preload="metadata" src="drop_front.mp4">' in html
    assert 'src="front.png"' in html
    assert html.count("<polyline") == 2  # the finger-force curve, one line per finger
    card = card_data(root)
    assert card.l3.ran and card.l3.force_t_s[-1] == 3.0
    assert max(f[0] for f in card.l3.finger_force_n) == pytest.approx(3.0)
    frames = {(f.view, f.t_s): f for f in card.drop_frames}
    assert frames[("front", 0.3)].still and frames[("front", 0.0)].still is None  # t = 0: from the video instead


def test_card_of_an_asset_without_l3_says_so(tmp_path: Path) -> None:
    root = _asset(tmp_path, "sponge")
    _, page = build_card(root)
    html = page.read_text(encoding="utf-8")
    assert "was not run for this asset (--no-l3)" in html
    material = json.loads((root / "material.json").read_text())
    assert si(material["metrics"]["effective_modulus_pa"], "Pa") in html
    assert (root / CARD_PNG).stat().st_size > 10_000


def test_card_command_on_a_non_asset_is_one_error_line_and_writes_nothing(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("not an asset")
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "card", str(tmp_path)], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and "asset.json" in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_card_does_not_depend_on_the_folder_name(tmp_path: Path) -> None:
    """The same asset in two folders gets the same card (titled by its request): a renamed or moved asset, and a
    cluster run beside a clean run of the same request, hold the same bytes."""
    a = _asset(tmp_path / "a", "sponge")
    b = tmp_path / "b" / "renamed_sponge"
    shutil.copytree(a, b)
    _, page_a = build_card(a)
    _, page_b = build_card(b)
    html = page_a.read_text(encoding="utf-8")
    assert page_b.read_text(encoding="utf-8") == html
    text = json.loads((a / "asset.json").read_text())["request"]["text"]
    assert f"<h1>Asset card: {text}</h1>" in html and "renamed_sponge" not in html
