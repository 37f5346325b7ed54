"""`deformsmith schema NAME`: the JSON Schema of an agent-facing model."""

from __future__ import annotations

import typer

from contracts.registry import SCHEMAS, schema_model
from flows.cli.apps import app, emit_json, fail


@app.command("schema")
def schema(
    name: str = typer.Argument(None, help="model name, e.g. Material, ShapeProgram, ActionPlan"),
    list_all: bool = typer.Option(False, "--list", help="list the model names"),
) -> None:
    """Print the JSON Schema of a data model (what an LLM agent must produce)."""
    if list_all or not name:
        for key in sorted(SCHEMAS):
            typer.echo(key)
        return
    try:
        model = schema_model(name)
    except KeyError:
        fail(f"unknown schema '{name}'; known: {', '.join(sorted(SCHEMAS))}")
    emit_json(model.model_json_schema())
