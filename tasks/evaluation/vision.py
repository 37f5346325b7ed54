"""The paper's 0-1 ratings of an asset's drop-protocol videos by a vision LLM (litellm): physical realism,
photorealism and semantic consistency with the request. Frames are sampled from the front and side MP4s and sent as
PNG data URLs; the answer must be JSON with the three ratings in [0, 1], and a malformed answer is fed back (at most
`retries` times) before the rating is given up with its reason. Nothing here runs without a configured model."""

from __future__ import annotations

import base64
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, Field, ValidationError

RATINGS = ("physical_realism", "photorealism", "semantic_consistency")
FRAMES_PER_VIEW = 4
FRAME_SIZE_PX = 256


class VisionRating(BaseModel):
    """One asset's ratings [0-1] and the model's reason."""

    physical_realism: float = Field(ge=0.0, le=1.0, description="does it fall, land and deform like the material")
    photorealism: float = Field(ge=0.0, le=1.0, description="does it look like a photograph of the object")
    semantic_consistency: float = Field(ge=0.0, le=1.0, description="is it the requested object")
    rationale: str = ""


class VisionRatingError(RuntimeError):
    """No valid rating after the retries (the reason names the last problem)."""


PROMPT = """You rate a simulated deformable object generated from this request: "{request}".
The images are frames of a 5 s gravity drop from a quarter of its height onto a table, at 0 s, 1.7 s, 3.3 s and 5 s,
first from the front, then from the side (the paper's drop protocol).
Rate, each from 0 (not at all) to 1 (fully):
- physical_realism: does it fall, land, deform and come to rest as the requested material would?
- photorealism: does it look like a photograph of a real object?
- semantic_consistency: is it recognisably the requested object?
Answer with JSON only: {{"physical_realism": x, "photorealism": x, "semantic_consistency": x, "rationale": "one sentence"}}"""


def video_frames(path: Path, n: int = FRAMES_PER_VIEW, size_px: int = FRAME_SIZE_PX) -> list[np.ndarray]:
    """n frames evenly spaced over a video, first and last included, as RGB uint8 arrays of at most size_px."""
    import imageio.v3 as iio

    small: list[np.ndarray] = []  # every frame, already downsampled: a 720p video is never held whole in memory
    step = 1
    for frame in iio.imiter(Path(path)):
        if frame.ndim != 3:
            raise ValueError(f"{path}: not a video with frames")
        if not small:
            step = max(1, int(np.ceil(max(frame.shape[:2]) / size_px)))
        small.append(np.ascontiguousarray(frame[::step, ::step, :3]))
    if not small:
        raise ValueError(f"{path}: not a video with frames")
    return [small[i] for i in np.linspace(0, len(small) - 1, n).round().astype(int)]


def png_data_url(frame: np.ndarray) -> str:
    """A frame as a data:image/png;base64 URL."""
    import imageio.v3 as iio

    return "data:image/png;base64," + base64.b64encode(iio.imwrite("<bytes>", frame, extension=".png")).decode()


def _content(response: Any) -> str:
    """The answer text of a litellm (or OpenAI-shaped dict) response."""
    choice = response["choices"][0] if isinstance(response, dict) else response.choices[0]
    message = choice["message"] if isinstance(choice, dict) else choice.message
    text = message["content"] if isinstance(message, dict) else message.content
    return text or ""


def rate_videos(request_text: str, videos: dict[str, Path], model: str,
                completion: Callable[..., Any] | None = None, retries: int = 2) -> VisionRating:
    """Ask `model` for the three ratings of the drop videos (front, side); VisionRatingError when no valid answer."""
    # lazy: tasks.agents.llm pulls litellm (~10 s), only when a vision model rates
    from tasks.agents.llm import extract_json

    if completion is None:
        import litellm

        completion = litellm.completion
    images = [{"type": "image_url", "image_url": {"url": png_data_url(f)}}
              for view in ("front", "side") if view in videos for f in video_frames(videos[view])]
    if not images:
        raise VisionRatingError("no drop-protocol video to rate (run without --no-videos)")
    messages: list[dict[str, Any]] = [{"role": "user", "content": [
        {"type": "text", "text": PROMPT.format(request=request_text)}, *images]}]
    problem = ""
    for _ in range(retries + 1):
        try:
            text = _content(completion(model=model, messages=messages, temperature=0.0))
        except Exception as exc:  # noqa: BLE001  (the provider's error is the reason; a retry may help)
            problem = f"{type(exc).__name__}: {exc}"
            continue
        try:
            return VisionRating.model_validate_json(extract_json(text))
        except (ValueError, ValidationError) as exc:
            problem = str(exc).splitlines()[0]
            messages += [{"role": "assistant", "content": text},
                         {"role": "user", "content": f"That answer was not valid ({problem}). Answer with the JSON "
                                                     "object only, each rating a number from 0 to 1."}]
    raise VisionRatingError(f"{model}: no valid rating after {retries + 1} tries ({problem})")


def with_ratings(record: Any, request_text: str, model: str, completion: Callable[..., Any] | None = None) -> Any:
    """An ArmResult with the ratings of its asset's drop videos as metrics rating_<name> (evidence: model and reason),
    or, when rating failed, the reason in evidence['vision_rating_error'] and no rating metrics."""
    videos = {v: Path(record.asset_dir) / "renders" / f"drop_{v}.mp4" for v in ("front", "side")}
    videos = {v: p for v, p in videos.items() if p.is_file()}
    evidence = dict(record.evidence)
    metrics = dict(record.metrics)
    try:
        rating = rate_videos(request_text, videos, model, completion)
    except (VisionRatingError, ValueError, OSError) as exc:
        evidence["vision_rating_error"] = str(exc)
    else:
        metrics.update({f"rating_{k}": float(getattr(rating, k)) for k in RATINGS})
        evidence["vision_rating"] = {"model": model, "rationale": rating.rationale,
                                     "frames_per_view": FRAMES_PER_VIEW, "views": sorted(videos)}
    return record.model_copy(update={"metrics": metrics, "evidence": evidence})


__all__ = ["RATINGS", "VisionRating", "VisionRatingError", "rate_videos", "video_frames", "with_ratings"]
