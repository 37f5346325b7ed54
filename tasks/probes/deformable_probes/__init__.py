"""L2's deformable probes, one module each (`PROBE`), found by tasks/probes/registry.py."""
