"""Moved to tasks.render.discs (one rendering package, #37): this name re-exports it for its callers."""

from tasks.render.discs import Camera, render

__all__ = ["Camera", "render"]
