"""`deployments/gpu_wheels.py park / unpark`: the evidence folders leave what a device call carries and come back
whole; a kept results folder stays; nothing is lost when unpark would overwrite."""

from __future__ import annotations

import importlib.util
import subprocess
from pathlib import Path

import pytest

_SPEC = importlib.util.spec_from_file_location("gpu_wheels", Path(__file__).parents[2] / "deployments" / "gpu_wheels.py")
assert _SPEC is not None and _SPEC.loader is not None
gpu_wheels = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(gpu_wheels)


def _repo(root: Path) -> dict[str, bytes]:
    files = {"docs/blind/s1/sheet.jpg": b"jpeg", "docs/results/run-a/r.json": b"{}", "docs/results/run-b/log.txt": b"l",
             "docs/results/index.md": b"# runs", "tasks/x.py": b"x = 1\n"}
    for rel, data in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_bytes(data)
    subprocess.run(["git", "init", "-q", str(root)], check=True)
    return files


def _carried(root: Path) -> set[str]:
    """What a device call sends: tracked and untracked files git does not ignore, that exist."""
    out = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=root,
                         check=True, capture_output=True).stdout.decode()
    return {p for p in out.split("\0") if p and (root / p).is_file()}


def test_park_moves_the_evidence_out_of_the_carried_tree_and_unpark_restores_it(tmp_path: Path) -> None:
    files = _repo(tmp_path)
    moved = gpu_wheels.park(tmp_path, ["docs/results/run-b"])
    assert moved == ["docs/blind", "docs/results/index.md", "docs/results/run-a"]
    assert _carried(tmp_path) == {"docs/results/run-b/log.txt", "tasks/x.py"}
    with pytest.raises(SystemExit, match="unpark"):
        gpu_wheels.park(tmp_path, [])  # parked already: refused
    assert sorted(gpu_wheels.unpark(tmp_path)) == sorted(moved)
    assert {rel: (tmp_path / rel).read_bytes() for rel in files} == files
    assert not (tmp_path / gpu_wheels.PARKED).exists()


def test_unpark_refuses_to_overwrite_and_moves_nothing(tmp_path: Path) -> None:
    _repo(tmp_path)
    gpu_wheels.park(tmp_path, [])
    (tmp_path / "docs/blind").mkdir(parents=True)  # something new where a parked folder goes back
    with pytest.raises(SystemExit, match="docs/blind exists"):
        gpu_wheels.unpark(tmp_path)
    assert (tmp_path / gpu_wheels.PARKED / "docs/blind/s1/sheet.jpg").read_bytes() == b"jpeg"
