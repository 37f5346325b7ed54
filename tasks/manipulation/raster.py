"""Moved to tasks.render.mesh_raster (one rendering package, #37): this name re-exports it for its callers."""

from tasks.render.mesh_raster import (BACKGROUND, GRIPPER, NEAR_M, OBJECT, ROBOT, TABLE, CamFrame, Discs, Mesh, draw,
                                      project)

__all__ = ["BACKGROUND", "GRIPPER", "NEAR_M", "OBJECT", "ROBOT", "TABLE", "CamFrame", "Discs", "Mesh", "draw", "project"]
