"""L0 geometry: text / image / mesh -> aligned mesh, convex proxy, MPM particles and Gaussians (metres)."""
