"""The evidence as the console shows it: the per-stage tally table and its notes (`evidence`, `inspect` and
`generate` print the same one, counted by `tasks.record.stage_tallies`), the validation summary's tallies and key
figures, and each harness attempt as a heading and its detail lines."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rich.markup import escape
from rich.table import Table

from contracts.evidence import Attempt, StageTally
from contracts.manifest import AssetManifest
from tasks.record.tally import stage_tallies

VERDICT_STYLE = {"accepted": "green", "best_so_far": "green", "rejected": "red", "rolled_back": "yellow",
                 "revise": "yellow", "escalated": "yellow"}
ROLE_WORDS = {"held_out": "held-out", "other": "other"}
KEY_FIGURES = ("mass_kg", "effective_modulus_pa", "rebound_ratio", "recovery_ratio", "sag_ratio", "volume_m3",
               "max_finger_force_n", "place_error_m")


def short_of_targets(t: StageTally) -> bool:
    """A valid candidate was kept that missed a measured target. A record written before #36 says 'best_valid'
    when a target was only not measured: its own metrics say there was no miss, so it is no 'best valid'."""
    return bool(t.unmet_targets) or (t.status == "best_valid" and not t.not_measured)


def passed_word(t: StageTally) -> str:
    """'yes', 'best valid' (a valid candidate kept, a measured target missed) or 'NO'."""
    if not t.passed:
        return "[red]NO[/red]"
    return "[yellow]best valid[/yellow]" if short_of_targets(t) else "[green]yes[/green]"


def sims_parts(t: StageTally) -> str:
    """'12 simulations = 6 in the harness loop + 2 screening + 4 held-out' (a stage that ran some outside it)."""
    parts = [f"{t.loop_sim_calls} in the harness loop"] + [f"{n} {ROLE_WORDS.get(r, r)}"
                                                             for r, n in t.extra_sim_calls.items()]
    return f"{t.sim_calls} simulations = " + " + ".join(parts)


def tally_table(tallies: list[StageTally], figures: dict[str, str] | None = None, title: str = "stages") -> Table:
    """stage | passed | attempts | simulations [| key figures]: the one table of counts every command prints."""
    table = Table(title=title, title_justify="left")
    table.add_column("stage", no_wrap=True)
    table.add_column("passed", no_wrap=True)
    table.add_column("attempts", justify="right", no_wrap=True)
    table.add_column("simulations", justify="right", no_wrap=True)
    if figures is not None:  # wrapped between figures, never inside one: as wide as the longest 'name=value,'
        widest = max((len(word) for text in figures.values() for word in text.split()), default=0)
        table.add_column("key figures", overflow="fold", ratio=1, min_width=widest)
    for t in tallies:
        row = [t.stage, passed_word(t), str(t.attempts), str(t.sim_calls)]
        table.add_row(*row, *([escape(figures.get(t.stage, ""))] if figures is not None else []))
    return table


def tally_notes(tallies: list[StageTally]) -> list[str]:
    """Below the table, in full: where the simulations outside a harness loop went, and why a stage did not
    simply pass."""
    lines = [f"{t.stage}: {sims_parts(t)}" for t in tallies if t.extra_sim_calls]
    for t in tallies:
        if not t.passed:
            lines.append(f"{t.stage}: NO — {t.message or t.status}")
        elif short_of_targets(t):
            unmet = ", ".join(t.unmet_targets) or "see evidence"
            lines.append(f"{t.stage}: best valid — the best valid candidate was kept; targets not met: {unmet}")
        for metric, why in t.not_measured.items():
            lines.append(f"{t.stage}: {metric} not measured — {why}")
    return lines


def validation_tallies(manifest: AssetManifest, asset_dir: Path) -> tuple[list[StageTally], dict[str, str]]:
    """The validation summary of an asset: its tallies, counted from the attempt records (the same tallies
    `evidence` prints), by stage, and each stage's key figures from the manifest ('name=value, ...')."""
    figures = {s.stage: ", ".join(f"{k}={s.metrics[k]:.3g}" for k in KEY_FIGURES if k in s.metrics)
               for s in manifest.validation}
    tallies: dict[str, StageTally] = {t.stage: t for t in stage_tallies(asset_dir)}
    for s in manifest.validation:  # a directory without its records (copied asset.json alone): the manifest's line
        if s.stage not in tallies:
            tallies[s.stage] = StageTally(stage=s.stage, status="passed" if s.passed else "failed", passed=s.passed,
                                          attempts=s.attempts, loop_sim_calls=s.sim_calls,
                                          message=s.reason or ", ".join(s.failed_gates))
    return sorted(tallies.values(), key=lambda t: t.stage), figures


def _fmt(v: Any) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def attempt_trials(root: Path, a: Attempt) -> list[int]:
    """The trial numbers (tasks.record.trials: one numbering with the console, manipulation.json and the card) of an
    L3 harness attempt's simulated pick-and-places, from the interaction folders its evidence names."""
    # lazy: contracts.asset_dir's models (~0.1 s; --help imports every command module)
    from tasks.record.trials import read_record, trial_of_folder

    record = read_record(root) if a.stage == "L3" else None  # typed; None when absent or not a valid record
    if record is None:
        return []
    found = [trial_of_folder(record, rec) for rec in a.evidence.recordings]
    return [n for n in found if n is not None]


def trial_data(root: Path, trials: list[int]) -> str:
    """Where the states of an L3 attempt's trials are: 'states: trial 2 interaction/attempt_001' or, for a trial the
    asset left in the cache (tasks.manipulation.keep), 'trial 1 in the cache, key ...' ('' when none is known)."""
    # lazy: contracts.asset_dir's models (~0.1 s; --help imports every command module)
    from tasks.record.trials import data_location, read_record, trial_rows

    record = read_record(root)
    if record is None or not trials:
        return ""
    rows = {row.trial: row for row in trial_rows(record)}
    parts = [f"trial {n} {data_location(rows[n], root)}" for n in trials if n in rows]
    return "states: " + "; ".join(parts) if parts else ""


def attempt_block(a: Attempt, trials: list[int] | None = None, where: str = "") -> list[str]:
    """An attempt as a heading line and indented detail lines (one line each, never wrapped nor cut); an L3 attempt
    names its trial numbers, and `where` their states are (trial_data)."""
    src = a.source.backend + (f"/{a.source.model}" if a.source.model else "")
    if a.source.retries:
        src += f", {a.source.retries} retries"
    style = VERDICT_STYLE.get(a.verdict)
    verdict = f"[{style}]{a.verdict}[/{style}]" if style else a.verdict
    score = "" if a.score is None else f", score {a.score:.3f}"
    trial = (f" = trial {', '.join(map(str, trials))}" if trials else "")
    head = (f"[bold]{a.stage} #{a.iteration}{trial}[/bold] {escape(a.action)} ({escape(src)}): {verdict}{score}, "
            f"{a.evidence.sim_calls} simulation{'' if a.evidence.sim_calls == 1 else 's'}")
    failed = [g.gate for g in a.gates if not g.passed]
    gates = ("failed gates: " + ", ".join(failed)) if failed else ("gates: all pass" if a.gates else "not probed")
    why = a.rejected_before_probe or (f"[{a.diagnosis}] " if a.diagnosis else "") + (a.critique or a.rationale)
    values = ", ".join(f"{k}={_fmt(v)}" for k, v in a.proposal.items()) or "-"
    return [head, escape(values), escape(gates), escape(why or "-"), *([escape(where)] if where else [])]
