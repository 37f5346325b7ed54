"""`deformsmith eval`: a suite's cases through the paper's ablations (Table III), records, then the report.

Layout under OUT: ``cases/<case>/<arm>/`` (the asset directories each arm built), ``records/<ablation>/<arm>/<case>.json``
(one `ArmResult` each, written atomically), ``report/`` (Markdown, PNG plots, figures.json). Resume: a case whose
records all exist is skipped; everything else re-runs against the content cache, so finished probes are hits.
Cases fan out over processes (``workers``); each case runs its arms in order inside one process.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

import cache  # noqa: F401  (local Prefect environment before prefect is imported)
from cache.runtime import set_env, shared_server_env
from contracts.evaluation import ArmResult, Condition, SuiteCase
from contracts.agents import AgentConfig
from contracts.sim import SimConfig
from flows import eval_arms, l0_geometry
from tasks.evaluation.arms import harness_result, hierarchy_result
from tasks.evaluation.runs import ALL, EvalOptions, case_done, load_records, needed_arms, not_built, write_record
from tasks.evaluation.suite import load_suite, select, to_request
from tasks.evaluation.report import write_report
from tasks.probes.workers import child_probe_workers
from tasks.evaluation.vision import with_ratings
from prefect import flow

Progress = Callable[[str], None]


def run_case(case: SuiteCase, suite_file: Path, opts: EvalOptions, conditions: list[Condition]) -> list[str]:
    """Every needed arm of one case; returns the record paths written."""
    out = Path(opts.out)
    image_dir = Path(cache.cache_root()) / "eval_images"
    request = to_request(case, suite_file.parent, image_dir, opts.quality)  # type: ignore[arg-type]
    sim = SimConfig(device=opts.device)
    agents = AgentConfig.llm(opts.llm) if opts.llm else None
    needed = needed_arms(case, opts.ablations)
    written: list[str] = []

    def keep(r: ArmResult) -> None:
        if (r.ablation, r.arm) in needed:
            written.append(str(write_record(out, r)))

    t0 = time.perf_counter()
    l0 = l0_geometry.run_l0(request, quality=request.quality)
    base = out / "cases" / case.id
    if not l0.checks.passed:
        for r in not_built(case, needed, f"L0 gates failed: {', '.join(l0.checks.failed)}", time.perf_counter() - t0):
            keep(r)
        return written
    l0_wall = time.perf_counter() - t0
    h: dict[str, Any] | None = None
    if any(a in opts.ablations for a in ALL):
        t1 = time.perf_counter()
        h = eval_arms.run_hierarchical(case, request, l0, base / "hierarchical", sim, agents, videos=opts.videos)
        wall = l0_wall + time.perf_counter() - t1
        ours = hierarchy_result(case, h, wall)
        rater = opts.vision_llm or opts.llm
        if rater and opts.videos and ours.delivered:
            ours = with_ratings(ours, request.text or request.material_intent or case.id, rater)
        keep(ours)
        keep(harness_result(case, h, wall - l0_wall))
    if "harness" in opts.ablations and h is not None:
        keep(eval_arms.run_one_shot(case, request, h, sim, time.perf_counter()))
    if "hierarchy" in opts.ablations:
        t2 = time.perf_counter()
        keep(eval_arms.run_flat(case, request, l0, base / "flat", sim, agents, t2 - l0_wall))
    if "manipulation" in opts.ablations and case.manipulation and h is not None:
        for r in eval_arms.run_manipulation(case, request, h, base, conditions, sim, agents, opts.quality):
            keep(r)
    return written


_set_env = set_env  # the worker initializer lives in cache.runtime: unpickling it in a spawned worker must not import
# Prefect (this module does), or Prefect's settings are read before the environment they depend on is set


def _case_job(case_json: str, suite_file: str, opts: EvalOptions, conditions: list[dict]) -> dict[str, Any]:
    """Process entry point: one case, errors caught (a crashed case fails alone, with its reason)."""
    case = SuiteCase.model_validate_json(case_json)
    t0 = time.perf_counter()
    try:
        paths = run_case(case, Path(suite_file), opts, [Condition.model_validate(c) for c in conditions])
        return {"case": case.id, "ok": True, "records": paths, "wall_s": time.perf_counter() - t0}
    except Exception as exc:  # noqa: BLE001  (reported per case; the evaluation goes on)
        return {"case": case.id, "ok": False, "error": f"{type(exc).__name__}: {exc}",
                "trace": traceback.format_exc(limit=8), "wall_s": time.perf_counter() - t0}


def evaluate(opts: EvalOptions, progress: Progress | None = None) -> dict[str, Any]:
    """Run (or resume) an evaluation and write its report; returns the summary (figures, paths, wall time)."""
    say = progress or (lambda msg: None)
    suite, suite_file = load_suite(opts.suite)
    conditions = list(opts.conditions or suite.manipulation_conditions)
    only_c = opts.ablations == ("manipulation",)
    cases = select(suite, opts.limit, list(opts.case_ids) or None, manipulation=only_c)
    if "manipulation" in opts.ablations and not only_c and opts.limit is not None:
        extra = [c for c in select(suite, None, list(opts.case_ids) or None, manipulation=True)[:opts.limit]
                 if c not in cases]
        cases += extra  # --limit N also gives ablation C N of its assets
    out = Path(opts.out).absolute()
    out.mkdir(parents=True, exist_ok=True)
    opts = EvalOptions(**{**opts.__dict__, "out": out})
    todo = [c for c in cases if not case_done(out, c, opts.ablations)]
    say(f"{len(cases)} case(s), {len(cases) - len(todo)} already recorded, {len(todo)} to run "
        f"with {opts.workers} worker(s)")
    t0 = time.perf_counter()
    jobs: list[dict[str, Any]] = []
    cond_json = [c.model_dump(mode="json") for c in conditions]
    if opts.workers <= 1:
        for c in todo:
            say(f"case {c.id}: running")
            jobs.append(_case_job(c.model_dump_json(), str(suite_file), opts, cond_json))
            say(f"case {c.id}: {'ok' if jobs[-1]['ok'] else 'FAILED ' + jobs[-1]['error']} "
                f"({jobs[-1]['wall_s']:.0f} s)")
    else:
        import multiprocessing as mp

        # the workers share this process's local Prefect server instead of each starting one
        env = {**child_probe_workers(opts.workers), **shared_server_env()}
        with ProcessPoolExecutor(max_workers=opts.workers, mp_context=mp.get_context("spawn"),
                                 initializer=_set_env,  # the cases' probe threads share the cores
                                 initargs=(env,)) as pool:
            futs = {pool.submit(_case_job, c.model_dump_json(), str(suite_file), opts, cond_json): c for c in todo}
            for f in as_completed(futs):
                jobs.append(f.result())
                say(f"case {jobs[-1]['case']}: {'ok' if jobs[-1]['ok'] else 'FAILED ' + jobs[-1].get('error', '')} "
                    f"({jobs[-1]['wall_s']:.0f} s)")
    wall = time.perf_counter() - t0
    ids = {c.id for c in cases}
    records = [r for r in load_records(out) if r.case_id in ids and r.ablation in opts.ablations]
    summary = write_report(out / "report", records, suite, suite_file, opts, wall, jobs)
    return summary


@flow(name="evaluate", persist_result=False, validate_parameters=False)
def evaluate_suite(opts: EvalOptions) -> dict[str, Any]:
    """The evaluation as one Prefect flow run (for deployments / a server); its cases fan out over worker processes,
    each running the layers' flows as runs of its own."""
    return evaluate(opts)


def evaluation_flow(opts: EvalOptions) -> dict[str, Any]:
    """The `evaluate` flow against the local Prefect runtime."""
    with cache.local_runtime():
        return evaluate_suite(opts)
