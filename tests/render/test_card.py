"""The asset card: built from the asset directory's records for an asset with L3 and one without, with the numbers of
material.json / physical.json / manipulation.json, the videos embedded by relative paths; a bad directory is one
`error:` line, exit 2, nothing written."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from tasks.render.card import CARD_HTML, CARD_PNG, build_card
from tasks.render.card_data import card_data
from tasks.render.card_text import si
from tests.cli_in_process import cli_in_process

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


def test_card_command_on_a_non_asset_is_one_error_line_and_writes_nothing(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "notes.txt").write_text("not an asset")
    code, err = cli_in_process("card", str(tmp_path), api=None, monkeypatch=monkeypatch, capsys=capsys)
    assert code == 2
    lines = err.strip().splitlines()
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


def _card_text(root: Path) -> str:
    """Every word the card shows: the HTML page and the PNG's text blocks (tasks.render.card_png's lines)."""
    from tasks.render import card_png

    card = card_data(root)
    png_lines = [*card_png._material_lines(card), *card_png._l1_lines(card), *card_png._l3_lines(card),
                 *card_png._stage_lines(card), *(v.sentence for v in card.layers), card.material_words or ""]
    import html

    return html.unescape((root / CARD_HTML).read_text(encoding="utf-8")) + "\n".join(png_lines)


def test_no_nan_on_a_card_and_every_target_measured_or_not_with_a_reason(tmp_path: Path) -> None:
    """#36: a failed trial's labels hold NaN where the object was never held (the duck's 'hold normal force nan'): the
    card shows no NaN, the figure is absent with its reason; each target band is measured inside, measured outside or
    not measured with a reason (the turtle's sag_ratio: the lift probe's pinch slipped); the L2 verdict is PASSED."""
    root = _asset(tmp_path, "turtle")
    record = json.loads((root / "manipulation.json").read_text())
    for key in ("hold_normal_force_n", "hold_friction_ratio"):
        record["labels"][key] = float("nan")
    (root / "manipulation.json").write_text(json.dumps(record))  # NaN, as json.dumps writes it
    build_card(root)
    text = _card_text(root)
    assert "nan" not in text.lower().replace("nanoseconds", "")
    card = card_data(root)
    hold = {f.metric: f for f in card.l3.figures}["hold_normal_force_n"]
    assert hold.value is None and hold.state == "not measured" and "never held" in (hold.note or "")
    states = {f.metric: f.state for f in card.bands}
    assert set(states.values()) <= {"measured inside", "measured outside", "not measured"}
    assert states["sag_ratio"] == "not measured" and states["effective_modulus_pa"] == "measured inside"
    sag = {f.metric: f for f in card.bands}["sag_ratio"]
    assert sag.note and "pinch did not hold" in sag.note and f"not measured: {sag.note}" in text
    assert "OUTSIDE" not in text  # nothing was measured outside its band
    verdicts = {v.stage: v for v in card.layers}
    assert [v.stage for v in card.layers] == ["L0", "L1", "L2", "L3"]
    assert verdicts["L2"].passed and "Not measured: sag ratio" in verdicts["L2"].sentence
    assert card.material_words == "soft as a plush toy, hardly bounces: E = 9.98 kPa"


def test_card_reads_in_ten_seconds_then_the_technical_details(tmp_path: Path) -> None:
    """The page opens with the request, what was built, PASSED / NOT PASSED per layer and the material in plain
    words; probes, cache keys and harness words come after, in a section of their own."""
    root = _asset(tmp_path, "turtle")
    record = json.loads((root / "manipulation.json").read_text())
    record.update(passed=False, status="best_valid", message="not lifted: the object slipped out at lift")
    (root / "manipulation.json").write_text(json.dumps(record))
    _, page = build_card(root)
    html = page.read_text(encoding="utf-8")
    first, technical = html.split('<section class="technical">')
    assert first.count('class="mark">PASSED<') == 3 and first.count('class="mark">NOT PASSED<') == 1
    assert "soft as a plush toy" in first and "plush turtle" in first
    for word in ("best_valid", "cache key", "CacheStore", 'class="key"'):
        assert word not in first and word in technical
    assert "font-family:monospace" not in html.split("body{")[1].split("}")[0]


def test_one_trial_numbering_in_manipulation_json_evidence_and_the_card(tmp_path: Path) -> None:
    """A trial is a simulated pick-and-place, numbered from 1 in the order run (the console's 'L3 trial k'):
    manipulation.json's rows (trial_rows), `deformsmith evidence` (the harness attempt's trial) and the card name the
    same number for the same interaction folder; never the folder index."""
    from tasks.report.evidence import attempt_trials
    from tasks.agents.records import read_attempts
    from tasks.asset_dir import AssetDir
    from tasks.record.trials import trial_of_attempt, trial_rows

    root = _asset(tmp_path, "turtle")
    record = json.loads((root / "manipulation.json").read_text())
    typed = AssetDir(root).manipulation()  # a record written before #36: its rows have no `trial`
    assert all(a.trial is None for a in typed.attempts)
    rows = trial_rows(typed)
    assert [r.trial for r in rows] == [1, 2, 3, 4] and [r.attempt for r in rows] == [0, 1, 2, 3]
    l3 = [a for a in read_attempts(root / "evidence" / "attempts.jsonl") if a.stage == "L3"]
    assert [attempt_trials(root, a) for a in l3] == [[1]]  # the harness's attempt #0 ran trial 1
    card = card_data(root)
    assert (card.l3.trial, card.l3.trials) == (trial_of_attempt(typed, typed.attempt), 4) == (1, 4)
    _, page = build_card(root)
    html = page.read_text(encoding="utf-8")
    assert "trial 1 of 4" in html and "trial 0" not in html
    assert any(s.startswith("L3: accepted, 4 trial(s)") and s.endswith("reported: trial 1") for s in card.stages)
    record.update(attempt=2, trial=3)  # a record that reports a later trial: the card follows manipulation.json
    (root / "manipulation.json").write_text(json.dumps(record))
    assert card_data(root).l3.trial == 3


def test_card_says_which_part_the_grasp_holds_and_why(tmp_path: Path) -> None:
    """The Planner's part preference (tasks.robot.grasp_parts) recorded in the plan is on the card."""
    root = _asset(tmp_path, "turtle")
    doc = json.loads((root / "manipulation.json").read_text())
    doc["plan"]["grasp_reason"] = "held by the shell, the body (parts told by the shape program's parts)"
    (root / "manipulation.json").write_text(json.dumps(doc))
    _, page = build_card(root)
    assert "grasp: held by the shell, the body" in page.read_text(encoding="utf-8")


def test_trials_left_in_the_cache_are_named_by_key_never_by_a_missing_path(tmp_path: Path) -> None:
    """A default asset keeps the reported trial's states alone (#38 item 5): the card and `evidence` say where the
    others are ('in the cache, key ...'), and name no interaction folder the asset does not hold."""
    from tasks.report.evidence import attempt_trials, trial_data
    from tasks.agents.records import read_attempts

    root = _asset(tmp_path, "turtle")
    record = json.loads((root / "manipulation.json").read_text())
    for row in record["attempts"]:
        row["data_key"] = f"{row['attempt']:x}" * 64
        if row["attempt"] != record["attempt"]:
            row.update(kept_in="cache", recording=None)
    (root / "manipulation.json").write_text(json.dumps(record))
    card = card_data(root)
    assert card.l3.data == "interaction/attempt_000"
    assert card.l3.others is not None and card.l3.others.startswith("trials 2-4: states and recordings in the cache")
    _, page = build_card(root)
    html = page.read_text(encoding="utf-8")
    assert "(interaction/attempt_000)" in html and "trials 2-4: states and recordings in the cache" in html
    assert not any(f"interaction/attempt_{n:03d}" in html for n in (1, 2, 3))
    l3 = [a for a in read_attempts(root / "evidence" / "attempts.jsonl") if a.stage == "L3"]
    assert trial_data(root, attempt_trials(root, l3[0])) == "states: trial 1 interaction/attempt_000"
    record.update(attempt=2, trial=3)  # the asset reports trial 3: trial 1's states are in the cache
    for row in record["attempts"]:
        row["kept_in"] = "asset" if row["attempt"] == 2 else "cache"
    (root / "manipulation.json").write_text(json.dumps(record))
    assert trial_data(root, [1]) == f"states: trial 1 in the cache, key {'0' * 12}"
    card = card_data(root)
    assert card.l3.data == "in the cache, key 222222222222"  # its folder is not in this asset: no path is named
    assert card.l3.others is not None and card.l3.others.startswith("trials 1-2, 4:")
