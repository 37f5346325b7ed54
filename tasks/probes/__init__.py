"""Probes: rigid (pybullet) and deformable (MPM) experiments that return evidence."""
