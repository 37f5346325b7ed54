"""`deformsmith evidence ASSET_OR_RUN`: the harness's attempt history as a table (or JSON)."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.markup import escape
from rich.table import Table

from contracts.agents import StageOutcome
from contracts.errors import InputError
from flows.cli.apps import app, console, emit_json, fail


def _fmt_values(values: dict) -> str:
    return "\n".join(f"{k}={v:.4g}" if isinstance(v, (int, float)) else f"{k}={v}" for k, v in values.items()) or "-"


@app.command("evidence")
def evidence(
    path: Path = typer.Argument(..., help="asset directory, run directory (searched recursively) or attempts.jsonl"),
    stage: str = typer.Option(None, "--stage", help="only this stage: L0 | L1 | L2 | L3"),
    as_json: bool = typer.Option(False, "--json", help="print the attempt records as JSON"),
) -> None:
    """Print the harness's attempt history: proposal, source, evidence, gates, verdict."""
    from tasks.agents.records import find_attempt_files, read_attempts

    try:
        files = find_attempt_files(path)
        records = [(f, a) for f in files for a in read_attempts(f)]
    except InputError as exc:
        fail(str(exc))
    if not files:
        fail(f"{path}: no evidence/attempts.jsonl found")
    if stage:
        records = [(f, a) for f, a in records if a.stage == stage.upper()]
    if as_json:
        emit_json([{"file": str(f), **a.model_dump(mode="json")} for f, a in records])
        return
    for f in files:
        rows = [a for g, a in records if g == f]
        table = Table(title=str(f), show_lines=True)
        for col in ("stage", "#", "action", "source", "proposal [SI]", "score", "failed gates", "verdict", "why"):
            table.add_column(col, overflow="fold")
        for a in rows:
            src = a.source.backend + (f"\n{a.source.model}" if a.source.model else "")
            if a.source.retries:
                src += f"\n({a.source.retries} retries)"
            failed = ", ".join(g.gate for g in a.gates if not g.passed) or ("-" if a.gates else "not probed")
            why = a.rejected_before_probe or (f"[{a.diagnosis}] " if a.diagnosis else "") + (a.critique or a.rationale)
            style = {"accepted": "green", "rejected": "red", "rolled_back": "yellow", "revise": "yellow"}.get(a.verdict)
            table.add_row(a.stage, str(a.iteration), a.action, escape(src), _fmt_values(a.proposal),
                          "-" if a.score is None else f"{a.score:.3f}", failed,
                          f"[{style}]{a.verdict}[/{style}]" if style else a.verdict, escape(why[:200]))
        console.print(table)
        for outcome in sorted(f.parent.glob("*_outcome.json")):
            try:
                o = StageOutcome.model_validate_json(outcome.read_text(encoding="utf-8"))
            except ValueError:
                continue
            if not stage or o.stage == stage.upper():
                colour = "green" if o.passed else "red"
                console.print(f"{o.stage}: [{colour}]{o.status}[/{colour}] ({o.attempts_used} attempts, "
                              f"{o.sim_calls} simulations): {escape(o.message)}")
