"""`deformsmith eval`: the paper's ablations (Table III) and the asset-quality protocol on a suite, with a report."""

from __future__ import annotations

from pathlib import Path

import typer

from cache import use_cache_root
from flows.cli.apps import app, check_device, console, emit_json, fail, results
from tasks.preflight import check_locations
from tasks.report.tables import eval_figure_lines

ABLATIONS = ("hierarchy", "harness", "manipulation")


@app.command("eval")
def eval_cmd(
    suite: str = typer.Option("default", "--suite", help="packaged suite name (contracts/suites) or a suite file"),
    ablation: str = typer.Option("all", "--ablation", help="hierarchy | harness | manipulation | a comma list | all"),
    limit: int = typer.Option(None, "--limit", min=1, help="only the first N cases (and N assets of ablation C)"),
    case: list[str] = typer.Option(None, "--case", help="only these case ids (repeatable)"),
    quality: str = typer.Option("draft", "--quality", help="draft | standard | high"),
    device: str = typer.Option("cpu", "--device", help="cpu | cuda"),
    workers: int = typer.Option(1, "--workers", min=1, help="cases run in parallel processes"),
    out: Path = typer.Option(Path("out/eval"), "--out", help="evaluation directory (records, cases, report)"),
    llm: str = typer.Option(None, "--llm", help="litellm model for every agent role (default: offline rule backend)"),
    videos: bool = typer.Option(True, "--videos/--no-videos", help="render the drop-protocol MP4s of our assets"),
    vision_llm: str = typer.Option(None, "--vision-llm", help="litellm model with vision that rates the drop videos "
                                   "0-1 (physical realism, photorealism, semantic consistency); default: --llm"),
    cache_dir: Path = typer.Option(None, "--cache", help="cache root"),
    as_json: bool = typer.Option(False, "--json", help="print the figures as JSON"),
) -> None:
    """Run (or resume) an evaluation: records per case and arm, then report.md with tables, plots and links."""
    chosen = ABLATIONS if ablation == "all" else tuple(a.strip() for a in ablation.split(","))
    if not chosen or any(a not in ABLATIONS for a in chosen):
        fail(f"--ablation must be one of {', '.join(ABLATIONS)}, a comma list of them, or all; got '{ablation}'")
    check_device(device)
    if quality not in ("draft", "standard", "high"):
        fail(f"--quality must be draft, standard or high, got '{quality}'")
    if vision_llm and not videos:
        fail("--vision-llm rates the drop-protocol videos: drop --no-videos")
    if cache_dir is not None:
        use_cache_root(cache_dir)
    check_locations(out_root=out)  # the evaluation folder and the cache root are usable, before any case runs
    from flows.evaluate import EvalOptions, evaluate  # lazy: Prefect and every layer's flow (seconds at CLI start)
    from tasks.evaluation.suite import load_suite  # lazy: numpy and the harness's vocabulary (0.8 s at CLI start)

    load_suite(suite)  # a bad suite fails here, before anything runs
    opts = EvalOptions(suite=suite, ablations=tuple(a for a in ABLATIONS if a in chosen), limit=limit,
                       case_ids=tuple(case or ()), quality=quality, device=device, workers=workers, out=out,
                       llm=llm, videos=videos, vision_llm=vision_llm)
    summary = evaluate(opts, progress=lambda msg: console.log(msg))
    if as_json:
        emit_json(summary)
        return
    results.print(f"report: {summary['report']}", markup=False, highlight=False)
    for line in eval_figure_lines(summary["figures"]):
        results.print(line)
    if summary["failed_cases"]:
        results.print(f"{len(summary['failed_cases'])} case(s) crashed; see the report")
