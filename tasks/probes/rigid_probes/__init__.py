"""L1's rigid probes, one module each (`PROBE`), found by tasks/probes/registry.py."""
