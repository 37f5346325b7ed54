"""Exports of an asset to other simulators (tet mesh, MuJoCo, Genesis, OpenUSD, Drake, SOFA); see registry.py."""
