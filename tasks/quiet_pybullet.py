"""pybullet without its build banner ('pybullet build time: ...'), which its C module prints at import: import
pybullet from here (`from tasks.quiet_pybullet import pybullet as pb`)."""

from tasks.native_output import native_output_filtered

with native_output_filtered(("pybullet build time",)):
    import pybullet

__all__ = ["pybullet"]
