"""What a fully cached rerun of `generate` no longer pays for: subflow parameters walked for the API, interaction
attempts compressed again, a duplicate pick-and-place recording, the interpreter's teardown at exit."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cache.hashing import path_digest
from cache.prefect_flow import LeanFlow, lean_flow, parameter_summary
from contracts.sim import SimConfig

REPO = Path(__file__).resolve().parents[2]


class _Runner:
    """A probe runner holding a big array, as L2's does (its mesh, particles and trimesh caches)."""

    def __init__(self) -> None:
        self.particles_m = np.zeros((100_000, 3))

    def __call__(self, values: dict[str, float], action: str) -> list[object]:
        return []


def test_a_lean_flow_records_plain_values_and_models_and_names_everything_else() -> None:
    @lean_flow(name="t-lean", validate_parameters=False, persist_result=False)
    def stage(asset_dir: Path, sim: SimConfig, runner: _Runner, values: dict[str, float]) -> int:
        return 1

    assert isinstance(stage, LeanFlow) and stage.name == "t-lean"
    recorded = stage.serialize_parameters({"asset_dir": Path("/a/b"), "sim": SimConfig(),
                                           "runner": _Runner(), "values": {"e_pa": 1e4, "ok": True},
                                           "arrays": [np.zeros(3)], "many": list(range(1000))})
    assert recorded == {"asset_dir": "/a/b", "sim": SimConfig().model_dump(mode="json"), "runner": "<_Runner>",
                        "values": {"e_pa": 1e4, "ok": True}, "arrays": ["<ndarray>"], "many": "<list>"}
    assert parameter_summary(None) is None and parameter_summary(print) == "<builtin_function_or_method>"


def _trial_arrays() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(0)
    return {"control_t_s": np.arange(6) * 0.01, "phase": np.arange(6) % 3,
            "particles_x_m": rng.random((4, 50, 3), dtype=np.float32) * 0.1,
            "particles_F": np.tile(np.eye(3, dtype=np.float32), (4, 50, 1, 1))}


def test_an_encoded_attempt_is_copied_on_a_rerun_not_compressed_again(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    import tasks.manipulation.context as l3
    from tasks.manipulation.data import read_attempt

    attrs = {"labels": {"lifted": 1.0, "hold_normal_force_n": float("nan")}, "role": "selection", "cache_key": "k"}
    assert l3.store_attempt(tmp_path / "a", _trial_arrays(), attrs) == 0

    def no_encoding(*args: object, **kwargs: object) -> int:
        raise AssertionError("the attempt was encoded again")

    monkeypatch.setattr(l3, "write_attempt", no_encoding)
    assert l3.store_attempt(tmp_path / "b", _trial_arrays(), attrs) == 0  # the same trial: copied
    assert path_digest(tmp_path / "b" / "interaction") == path_digest(tmp_path / "a" / "interaction")
    arrays, stored = read_attempt(tmp_path / "b", 0)
    assert stored["attempt"] == 0 and stored["role"] == "selection"
    np.testing.assert_allclose(arrays["particles_x_m"], _trial_arrays()["particles_x_m"], atol=5e-6)
    with pytest.raises(AssertionError, match="encoded again"):  # another index is another attempt: encoded
        l3.store_attempt(tmp_path / "b", _trial_arrays(), attrs)
    assert not [p for p in (tmp_path / "b" / "interaction").iterdir() if p.name.startswith(".")]  # nothing half-made


def test_the_chosen_trials_recording_is_renamed_not_copied(tmp_path: Path) -> None:
    from contracts.manipulation import TrialRow
    from tasks.manipulation.l3_record import PICK_AND_PLACE_RECORDING, name_pick_and_place

    (tmp_path / "recordings").mkdir()
    (tmp_path / "recordings" / "L3_trial_02.rrd").write_bytes(b"trial 1")
    chosen = TrialRow(attempt=1, role="selection", action="", labels={}, recording="recordings/L3_trial_02.rrd")
    attempts = [chosen]
    named = name_pick_and_place(tmp_path, attempts, chosen)
    assert named.recording == PICK_AND_PLACE_RECORDING and named.attempt == 1 and attempts == [named]
    assert sorted(p.name for p in (tmp_path / "recordings").iterdir()) == ["L3_pick_and_place.rrd"]
    assert (tmp_path / PICK_AND_PLACE_RECORDING).read_bytes() == b"trial 1"
    assert name_pick_and_place(tmp_path, attempts, named) is named  # named already: nothing moves
    assert (tmp_path / PICK_AND_PLACE_RECORDING).read_bytes() == b"trial 1"


_FLOW_COMMAND = """
import atexit, sys, threading
from flows.cli import main as cli_main

def command():
    print("summary line")
    threading._register_atexit(lambda: print("services drained"))  # as Prefect's queue services do
    atexit.register(lambda: print("exit hook ran", flush=False))
    if sys.argv[2] == "fail":
        raise SystemExit(7)

cli_main._main = command
sys.argv = ["deformsmith", "generate", sys.argv[1]]
cli_main.main()
print("never printed: main ends the process")
"""


@pytest.mark.parametrize("outcome, code", [("ok", 0), ("fail", 7)])
def test_a_flow_command_ends_after_its_exit_hooks_with_its_exit_code(outcome: str, code: int) -> None:
    proc = subprocess.run([sys.executable, "-c", _FLOW_COMMAND, outcome], capture_output=True, text=True, cwd=REPO,
                          timeout=120, env={**os.environ, "PYTHONPATH": str(REPO)})
    assert proc.returncode == code, proc.stderr
    assert proc.stdout.splitlines() == ["summary line", "services drained", "exit hook ran"]
