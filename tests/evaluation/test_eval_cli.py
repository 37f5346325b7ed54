"""`deformsmith eval`: input errors, and a tiny end-to-end run of ablation B that resumes from its records."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli_in_process import cli_in_process

TINY = {"name": "tiny", "cases": [{"id": "cube", "kind": "text", "text": "a soft foam cube 3 cm",
                                   "intent": "soft foam", "expected_material": "pu_foam"}]}


def _cli(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "flows.cli.main", "eval", *args], capture_output=True, text=True,
                          env=env)


def _cli_here(*args: str, api: str, monkeypatch: pytest.MonkeyPatch,
              capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """`deformsmith eval ARGS` in this process (tests/cli_in_process.py): (exit code, stderr)."""
    return cli_in_process("eval", *args, api=api, monkeypatch=monkeypatch, capsys=capsys)


def test_bad_inputs_fail_clearly(tmp_path: Path, cli_env: dict[str, str], prefect_api: str,
                                 monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    # the command as its own process once (against the session's Prefect server, conftest's cli_env: no command
    # starts one of its own beside the check): exit status and stderr as a user sees them
    r = _cli("--ablation", "nonsense", "--out", str(tmp_path / "o"), env=cli_env)
    assert r.returncode != 0 and "--ablation must be one of" in r.stderr
    # the other refusals through the same entry point in this process (no interpreter start-up per case)
    for args, words in ((("--suite", str(tmp_path / "none.yaml")), ("suite", "not found")),
                        (("--vision-llm", "some/vision-model", "--no-videos"),
                         ("--vision-llm rates the drop-protocol videos",)),
                        (("--ablation", "nonsense"), ("--ablation must be one of",))):
        code, err = _cli_here(*args, "--out", str(tmp_path / "o"), api=prefect_api, monkeypatch=monkeypatch,
                              capsys=capsys)
        assert code != 0 and all(w in err for w in words), (args, code, err)
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
@pytest.mark.timeout(1800)  # cold cache: L0, L1, L2 harness, one-shot, held-out probes, drop protocol (~10+ min loaded)
def test_harness_ablation_end_to_end(tmp_path: Path) -> None:
    suite = tmp_path / "tiny.json"
    suite.write_text(json.dumps(TINY))
    out = tmp_path / "eval"
    r = _cli("--suite", str(suite), "--ablation", "harness", "--limit", "1", "--no-videos", "--out", str(out),
             "--json")
    assert r.returncode == 0, r.stderr[-3000:]
    summary = json.loads(r.stdout)
    assert not summary["failed_cases"], summary["failed_cases"]
    figs = summary["figures"]["harness"]
    assert figs["harness"]["target_satisfaction"]["n"] == 1 and figs["one_shot"]["hard_failure"]["n"] == 1
    rec = json.loads((out / "records/harness/harness/cube.json").read_text())
    assert rec["delivered"] and rec["sim_calls"] > 0 and rec["evidence"]["cache_keys"]
    assert (out / "report/report.md").is_file() and (out / "report/harness.png").is_file()
    again = _cli("--suite", str(suite), "--ablation", "harness", "--out", str(out), "--json")
    assert again.returncode == 0 and "1 already recorded, 0 to run" in again.stderr
