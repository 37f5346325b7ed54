"""The harness's roles: rule and litellm backends, intent -> targets, the orchestrator loop and its records."""
