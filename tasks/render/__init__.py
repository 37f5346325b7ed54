"""CPU video renders of simulated assets (deformed Gaussians), deterministic, no display needed."""
