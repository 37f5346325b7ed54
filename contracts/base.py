"""Shared base for every boundary model: strict, immutable, canonical JSON."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict


class Model(BaseModel):
    """Frozen pydantic model that rejects unknown fields (typos fail loudly)."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)

    def canonical_json(self) -> str:
        """JSON with sorted keys and no whitespace: the form that is hashed."""
        import json

        return json.dumps(self.model_dump(mode="json"), sort_keys=True, separators=(",", ":"))
