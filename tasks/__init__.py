"""Units of work, one subpackage per concern (geometry, physical, mpm, probes, robot, agents, record)."""
