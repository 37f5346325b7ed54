"""`deformsmith evidence ASSET_OR_RUN`: the harness's attempt history (or JSON), and the per-stage tally table that
`inspect` and `generate` print too (one function, `tasks.record.stage_tallies`, counts for all three; the table and
the attempt lines are drawn by `tasks.report.evidence`)."""

from __future__ import annotations

from pathlib import Path

import typer
from rich.markup import escape

from contracts.errors import InputError
from contracts.evidence import StageTally
from flows.cli.apps import app, emit_json, fail, results
from tasks.record.attempts import find_attempt_files, read_attempts
from tasks.record.tally import stage_tallies
from tasks.report.evidence import attempt_block, attempt_trials, tally_notes, tally_table, trial_data


def print_tallies(tallies: list[StageTally], figures: dict[str, str] | None = None, title: str = "stages") -> None:
    """The tally table and its notes."""
    results.print(tally_table(tallies, figures, title))
    for line in tally_notes(tallies):
        results.print(line, markup=False, highlight=False)


@app.command("evidence")
def evidence(
    path: Path = typer.Argument(..., help="asset directory, run directory (searched recursively) or attempts.jsonl"),
    stage: str = typer.Option(None, "--stage", help="only this stage: L0 | L1 | L2 | L3"),
    as_json: bool = typer.Option(False, "--json", help="print the attempt records as JSON"),
) -> None:
    """Print the harness's attempt history: proposal, source, evidence, gates, verdict."""
    try:
        files = find_attempt_files(path)
        by_file = {f: read_attempts(f) for f in files}
    except InputError as exc:
        fail(str(exc))
    if not files:
        fail(f"{path}: no evidence/attempts.jsonl found")
    wanted = stage.upper() if stage else None
    if as_json:
        emit_json([{"file": str(f), **a.model_dump(mode="json")} for f, rows in by_file.items() for a in rows
                   if not wanted or a.stage == wanted])
        return
    for f, rows in by_file.items():
        root = f.parent.parent if f.parent.name == "evidence" else f.parent
        tallies = [t for t in stage_tallies(root, rows) if not wanted or t.stage == wanted]
        results.print(f"[bold]{escape(str(f))}[/bold]", highlight=False)
        print_tallies(tallies)
        for a in rows:
            if wanted and a.stage != wanted:
                continue
            trials = attempt_trials(root, a)
            head, *details = attempt_block(a, trials, trial_data(root, trials))
            results.print(head, highlight=False)
            for line in details:
                results.print("    " + line, highlight=False)
        for t in tallies:  # how each harness ended, in its own words
            if t.message and t.stage != "L0":
                results.print(f"[bold]{t.stage}[/bold] {t.status}: {escape(t.message)}", highlight=False)
