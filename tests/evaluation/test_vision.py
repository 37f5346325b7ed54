"""The paper's 0-1 vision-LLM ratings of our drop videos: frames from both views go to the configured model, a
malformed answer is fed back, a rating outside [0, 1] is refused, and the report shows what was rated."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from contracts.evaluation import ArmResult, Suite, SuiteCase
from tasks.evaluation.vision import VisionRatingError, rate_videos, video_frames, with_ratings

GOOD = {"physical_realism": 0.8, "photorealism": 0.4, "semantic_consistency": 0.9, "rationale": "squashes and rests"}


def _videos(folder: Path) -> dict[str, Path]:
    """Two 30 fps, 2 s MP4s of a square sinking (front: red, side: blue), as renders/ holds them."""
    import imageio.v3 as iio

    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for view, channel in (("front", 0), ("side", 2)):
        frames = np.zeros((60, 64, 64, 3), np.uint8)
        for i in range(60):
            top = 8 + i // 3
            frames[i, top:top + 16, 24:40, channel] = 255
        out[view] = folder / f"drop_{view}.mp4"
        iio.imwrite(out[view], frames, fps=30)
    return out


class FakeModel:
    """A completion function that records what it was sent and answers from a list."""

    def __init__(self, *answers: str) -> None:
        self.answers, self.calls = list(answers), []

    def __call__(self, model: str, messages: list, **kw: object) -> SimpleNamespace:
        self.calls.append({"model": model, "messages": [dict(m) for m in messages]})
        return SimpleNamespace(choices=[SimpleNamespace(message=SimpleNamespace(content=self.answers.pop(0)))])


def test_frames_of_both_views_go_to_the_model_and_its_json_is_the_rating(tmp_path: Path) -> None:
    videos = _videos(tmp_path / "renders")
    first, *_, last = video_frames(videos["front"])
    assert first.shape[2] == 3 and first[:, :, 0].argmax() < last[:, :, 0].argmax()  # the square sank
    model = FakeModel("Here you go:\n```json\n" + json.dumps(GOOD) + "\n```")
    r = rate_videos("a soft kitchen sponge", videos, "vision-model", completion=model)
    assert (r.physical_realism, r.photorealism, r.semantic_consistency) == (0.8, 0.4, 0.9)
    content = model.calls[0]["messages"][0]["content"]
    images = [c for c in content if c["type"] == "image_url"]
    assert len(images) == 8 and all(c["image_url"]["url"].startswith("data:image/png;base64,") for c in images)
    assert "a soft kitchen sponge" in content[0]["text"] and model.calls[0]["model"] == "vision-model"


def test_a_bad_answer_is_fed_back_and_out_of_range_ratings_are_refused(tmp_path: Path) -> None:
    videos = _videos(tmp_path / "renders")
    model = FakeModel("I think it looks fine.", json.dumps({**GOOD, "photorealism": 0.6}))
    assert rate_videos("a sponge", videos, "m", completion=model).photorealism == 0.6
    assert "not valid" in model.calls[1]["messages"][-1]["content"]  # the problem was named in the retry
    too_high = json.dumps({**GOOD, "physical_realism": 7})
    with pytest.raises(VisionRatingError, match="no valid rating after 3 tries"):
        rate_videos("a sponge", videos, "m", completion=FakeModel(too_high, too_high, too_high))
    with pytest.raises(VisionRatingError, match="no drop-protocol video"):
        rate_videos("a sponge", {}, "m", completion=FakeModel())


def test_ratings_reach_the_record_and_the_report(tmp_path: Path) -> None:
    from tasks.evaluation.runs import EvalOptions
    from tasks.evaluation.report import write_report

    asset = tmp_path / "cases" / "a" / "hierarchical"
    _videos(asset / "renders")
    rec = ArmResult(ablation="hierarchy", arm="hierarchical", case_id="a", case_kind="text", delivered=True,
                    physics_pass=True, asset_dir=str(asset))
    rated = with_ratings(rec, "a sponge", "vision-model", completion=FakeModel(json.dumps(GOOD)))
    assert rated.metrics["rating_semantic_consistency"] == 0.9
    assert rated.evidence["vision_rating"]["model"] == "vision-model"
    broken = with_ratings(rec.model_copy(update={"case_id": "b"}), "a sponge", "m",
                          completion=FakeModel("no", "no", "no"))
    assert "rating_photorealism" not in broken.metrics and "no valid rating" in broken.evidence["vision_rating_error"]
    flat = rec.model_copy(update={"arm": "flat"})
    suite = Suite(name="t", cases=[SuiteCase(id="a", kind="text", text="a sponge", intent="sponge")])
    md = Path(write_report(tmp_path / "report", [rated, broken, flat], suite, tmp_path / "s.yaml",
                           EvalOptions(ablations=("hierarchy",), llm="vision-model"), 1.0, [])["report"]).read_text()
    assert "| physical realism | 0.80 | 1 |" in md and "1 asset(s) rated, 1 not" in md
    plain = Path(write_report(tmp_path / "report2", [flat], suite, tmp_path / "s.yaml",
                              EvalOptions(ablations=("hierarchy",)), 1.0, [])["report"]).read_text()
    assert "None in this run: no vision LLM was configured" in plain
