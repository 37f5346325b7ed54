"""Every `deformsmith generate` input the README shows passes L3 at its default options on the CPU (#36): the default
turtle, "a red rubber duck, 10 cm long", "a plush cat" (shown with --device cuda: run here on the CPU) ... A line that
stops before the robot (--no-l3) has no L3 to pass; a line whose --image / --mesh file a fresh clone does not have
(photo.jpg, model.obj: the user's own) or that needs a reconstruction server (--geometry-backend) cannot be run here
and is listed as such. Slow: one generate takes 10-35 min on a loaded 2-core machine.
`python tests/generate/test_readme_inputs.py` runs it and prints one JSON row per input with its wall time."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
NEEDS_FILE = ("--image", "--mesh")


def readme_generate_commands(readme: Path = ROOT / "README.md") -> list[list[str]]:
    """The arguments after `deformsmith generate` of every such command in the README's shell blocks (comments and
    line continuations handled), in order, without duplicates."""
    text = readme.read_text(encoding="utf-8")
    out: list[list[str]] = []
    for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
        for line in block.replace("\\\n", " ").splitlines():
            for part in line.split("&&"):
                part = part.split(" # ")[0].strip()
                if part.startswith("deformsmith generate"):
                    args = shlex.split(part)[2:]
                    if args not in out:
                        out.append(args)
    return out


def runnable(args: list[str]) -> tuple[bool, str]:
    """Whether a README line can be run here to test L3 (and why not)."""
    if "--no-l3" in args:
        return False, "stops before L3 (--no-l3)"
    if "--geometry-backend" in args:
        return False, "needs a reconstruction server (--geometry-backend)"
    for flag in NEEDS_FILE:
        if flag in args and not (ROOT / args[args.index(flag) + 1]).is_file():
            return False, f"{flag} {args[args.index(flag) + 1]} is the user's own file"
    return True, ""


def cpu_args(args: list[str], out_dir: Path) -> list[str]:
    """The line's arguments on the CPU at its default options, into out_dir."""
    a = list(args)
    for flag in ("--device", "--out"):
        if flag in a:
            i = a.index(flag)
            del a[i:i + 2]
    return [*a, "--device", "cpu", "--out", str(out_dir)]


def run_line(args: list[str], out_dir: Path) -> dict[str, Any]:
    """`deformsmith generate` on one README line (CPU, its defaults): exit code, wall time, L3's outcome."""
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "flows.cli.main", "generate", *cpu_args(args, out_dir)],
                          capture_output=True, text=True, cwd=ROOT, env=dict(os.environ))
    row: dict[str, Any] = {"args": args, "exit": proc.returncode, "wall_s": round(time.perf_counter() - t0, 1)}
    path = out_dir / "manipulation.json"
    if not path.is_file():
        row.update(passed=False, error=(proc.stderr or proc.stdout).strip().splitlines()[-3:])
        return row
    rec = json.loads(path.read_text(encoding="utf-8"))
    row.update(passed=bool(rec.get("passed")), reason=rec.get("reason", ""), trials=len(rec.get("attempts") or []),
               trial=rec.get("trial"), gripper=(rec.get("gripper") or {}).get("name"),
               held_out=(rec.get("held_out") or {}).get("success_rate"))
    return row


def test_the_readme_shows_the_duck_and_the_default() -> None:
    """Fast: the parse finds the README's inputs (so the slow test below runs what a user reads)."""
    lines = readme_generate_commands()
    assert [] in lines  # the main job: `deformsmith generate` with no input, the default turtle
    assert ["a red rubber duck, 10 cm long"] in lines
    assert any(runnable(a)[0] and "cuda" in a for a in lines)  # a GPU line runs here on the CPU
    assert not runnable(["a gel pack", "--no-l3"])[0]


@pytest.mark.slow
@pytest.mark.timeout(4 * 3600)
def test_every_readme_input_passes_l3_on_the_cpu(tmp_path: Path) -> None:
    rows = []
    for i, args in enumerate(readme_generate_commands()):
        ok, why = runnable(args)
        rows.append(run_line(args, tmp_path / f"readme_{i}") if ok else {"args": args, "skipped": why})
        print(json.dumps(rows[-1]), flush=True)
    ran = [r for r in rows if "skipped" not in r]
    assert any(r["args"] == ["a red rubber duck, 10 cm long"] for r in ran)
    failed = [(r["args"], r.get("reason") or r.get("error")) for r in ran if not r["passed"]]
    assert not failed, failed


if __name__ == "__main__":
    work = Path(os.environ.get("README_INPUTS_DIR") or tempfile.mkdtemp(prefix="readme_inputs-"))
    for i, args in enumerate(readme_generate_commands()):
        ok, why = runnable(args)
        print(json.dumps(run_line(args, work / f"readme_{i}") if ok else {"args": args, "skipped": why}), flush=True)
