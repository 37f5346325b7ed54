"""Prefect flows (one per layer, the harness loop, generate, batch) and the CLI."""
