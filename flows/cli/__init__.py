"""The `deformsmith` command line."""
