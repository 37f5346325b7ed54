"""Evidence records: every attempt to evidence/attempts.jsonl (as it happens) and to a Rerun harness/log."""

from __future__ import annotations

import os
from pathlib import Path

from contracts.agents import StageOutcome
from contracts.evidence import Attempt
from tasks.record.attempts import ATTEMPTS_FILE, read_attempts


def attempt_line(a: Attempt) -> str:
    """One human-readable harness-log line for an attempt."""
    src = a.source.backend + (f"/{a.source.model}" if a.source.model else "")
    values = ", ".join(f"{k}={v:.4g}" for k, v in a.proposal.items() if isinstance(v, (int, float)))
    text = f"{a.stage}#{a.iteration} {a.action} [{src}] {values or '-'} -> {a.verdict}"
    if a.rejected_before_probe:
        text += f" (rejected: {a.rejected_before_probe})"
    if a.score is not None:
        text += f" score={a.score:.3f}"
    failed = [g.gate for g in a.gates if not g.passed]
    if failed:
        text += f" failed gates: {failed}"
    if a.diagnosis:
        text += f" diagnosis={a.diagnosis}"
    return text


def _level(a: Attempt) -> str:
    return {"accepted": "INFO", "best_so_far": "INFO", "rolled_back": "WARN", "revise": "WARN",
            "rejected": "ERROR", "escalated": "WARN"}.get(a.verdict, "INFO")


class AttemptRecorder:
    """Writes a stage's attempts under an asset/run directory; a rerun of the stage replaces that stage's lines."""

    def __init__(self, root: str | os.PathLike[str], stage: str, rrd: bool = True) -> None:
        self.root = Path(root)
        self.stage = stage
        self.path = self.root / ATTEMPTS_FILE
        self.rrd_path = self.root / "recordings" / f"harness_{stage}.rrd"
        self.rrd = rrd
        self.attempts: list[Attempt] = []
        self.path.parent.mkdir(parents=True, exist_ok=True)
        kept = [a for a in read_attempts(self.path) if a.stage != stage] if self.path.exists() else []
        tmp = self.path.with_name(self.path.name + f".{os.getpid()}.tmp")
        tmp.write_text("".join(a.model_dump_json() + "\n" for a in kept), encoding="utf-8")
        os.replace(tmp, self.path)

    def record(self, attempt: Attempt) -> None:
        """Append one attempt (flushed and fsynced: a killed run keeps every finished attempt)."""
        self.attempts.append(attempt)
        with open(self.path, "a", encoding="utf-8") as fh:
            fh.write(attempt.model_dump_json() + "\n")
            fh.flush()
            os.fsync(fh.fileno())

    def close(self, outcome: StageOutcome | None = None) -> None:
        """Write the stage outcome (evidence/<stage>_outcome.json) and the harness .rrd."""
        if outcome is not None:
            out = self.root / "evidence" / f"{self.stage}_outcome.json"
            tmp = out.with_name(out.name + ".tmp")
            tmp.write_text(outcome.model_dump_json(indent=2, exclude={"attempts"}), encoding="utf-8")
            os.replace(tmp, out)
        if self.rrd:
            write_harness_log(self.rrd_path, self.stage, self.attempts, outcome)


def write_harness_log(path: Path, stage: str, attempts: list[Attempt], outcome: StageOutcome | None = None) -> Path:
    """A Rerun recording with one harness/log TextLog per attempt (frame = iteration) and the score as a scalar."""
    from tasks.record.rerun_recording import ProbeRecording  # lazy: pulls rerun (1.3 s); reading records never does

    with ProbeRecording(path, recording_id=f"harness-{stage}") as rec:
        for a in attempts:
            rec.set_time(a.iteration, 0.0)
            rec.log(attempt_line(a), level=_level(a))
            if a.score is not None:
                rec.scalar("harness/score", a.score)
        if outcome is not None:
            rec.set_time(len(attempts), 0.0)
            rec.log(f"{stage} outcome: {outcome.status}: {outcome.message}",
                    level="INFO" if outcome.passed else "ERROR")
    return path
