"""What the user asks for: one input (text, image or mesh) plus hints."""

from __future__ import annotations

import re
import unicodedata
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from contracts.base import Model

Quality = Literal["draft", "standard", "high"]
InputKind = Literal["text", "image", "mesh"]
Pose = Literal["upright", "stable"]
# 'package.module:function' (an optional '#tag' names a version: change it to rebuild cached geometry) or an HTTP URL
GEOMETRY_BACKEND_PATTERN = r"(?:[A-Za-z_][\w]*(?:\.[A-Za-z_]\w*)*:[A-Za-z_]\w*(?:#\S*)?|(?:hunyuan3d\+)?https?://\S+)"


MIN_SIZE_M, MAX_SIZE_M = 0.01, 2.0  # the longest extent L0 can build [m]
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".glb", ".gltf", ".off")  # what L0 reads (tasks/geometry/mesh_import.py)
MAX_TEXT_CHARS = 1000  # a description, not a document: longer text is refused before any layer runs


def _check_words(name: str, value: str | None) -> None:
    """A description must be readable words: not longer than MAX_TEXT_CHARS, no control characters."""
    if value is None:
        return
    if len(value) > MAX_TEXT_CHARS:
        raise ValueError(f"{name} is {len(value)} characters long; at most {MAX_TEXT_CHARS} are read")
    bad = sorted({f"U+{ord(c):04X}" for c in value if unicodedata.category(c) in ("Cc", "Cs", "Co", "Cn")
                  and c not in "\t\n\r"})
    if bad:
        raise ValueError(f"{name} holds control characters ({', '.join(bad[:5])})")


class AssetRequest(Model):
    """A generation request; exactly one of text, image_path or mesh_path drives the geometry."""

    text: str | None = Field(default=None, description="description of the object, e.g. 'a soft plush turtle, 25 cm long'")
    image_path: Path | None = Field(default=None, description="PNG or JPEG of the object")
    mesh_path: Path | None = Field(default=None, description="OBJ/PLY/STL/GLB/OFF mesh file")
    size_hint_m: float | None = Field(
        default=None, gt=0, description="longest extent of the object [m]; overrides sizes parsed from the text"
    )
    material_intent: str | None = Field(
        default=None, description="words for the behaviour, e.g. 'soft plush', 'firm rubber'; default: from the text"
    )
    target_overrides: dict[str, tuple[float, float]] = Field(
        default_factory=dict, description="explicit target bands per probe metric, e.g. {'effective_modulus_pa': (2e4, 4e4)}"
    )
    seed: int = Field(default=0, description="seed of every random choice")
    geometry_backend: str | None = Field(
        default=None, description="reconstruction backend that makes the mesh from the text / image: a Python entry "
        "point 'module:function', an HTTP endpoint 'http(s)://...', or Hunyuan3D-2's API server 'hunyuan3d+http(s)://...' "
        "(tasks/geometry/backends.py); None: built in"
    )
    quality: Quality = Field(default="draft", description="resolution preset: draft | standard | high")
    pose: Pose = Field(default="upright", exclude_if=lambda v: v == "upright",
                       description="photo: 'upright' keeps the photo's vertical as the object's up (the table it "
                       "stands on is the ground); 'stable' puts it in its most stable resting pose. The default is "
                       "left out of the request's JSON, so requests that do not set it keep their cache keys")

    @model_validator(mode="after")
    def _exactly_one_input(self) -> AssetRequest:
        given = [n for n in ("text", "image_path", "mesh_path") if getattr(self, n) is not None]
        if self.text is not None and not self.text.strip() and self.image_path is None and self.mesh_path is None:
            raise ValueError("text is empty")
        if len(given) == 0:
            raise ValueError("give one input: text, image_path or mesh_path")
        for name in ("text", "material_intent"):
            _check_words(name, getattr(self, name))
        if self.mesh_path is not None and Path(self.mesh_path).suffix.lower() not in MESH_SUFFIXES:
            raise ValueError(f"unsupported mesh format '{Path(self.mesh_path).suffix}'; use one of "
                             f"{', '.join(MESH_SUFFIXES)}")
        if self.size_hint_m is not None and not (MIN_SIZE_M <= self.size_hint_m <= MAX_SIZE_M):
            raise ValueError(f"size_hint_m = {self.size_hint_m:g} m is outside the supported range "
                             f"[{MIN_SIZE_M:g}, {MAX_SIZE_M:g}] m")
        if self.image_path is not None and self.mesh_path is not None:
            raise ValueError("give either image_path or mesh_path, not both")
        if self.geometry_backend is not None:
            if self.mesh_path is not None:
                raise ValueError("a geometry backend builds the mesh from text or an image: give no mesh_path")
            if not re.fullmatch(GEOMETRY_BACKEND_PATTERN, self.geometry_backend.strip()):
                raise ValueError(f"geometry_backend '{self.geometry_backend}' is neither 'module:function' nor an "
                                 "http(s):// URL (or hunyuan3d+http(s)://, Hunyuan3D-2's API server)")
        return self

    @property
    def input_kind(self) -> InputKind:
        """Which geometry path this request takes (an image or mesh wins over text, which then describes it)."""
        if self.mesh_path is not None:
            return "mesh"
        if self.image_path is not None:
            return "image"
        return "text"
