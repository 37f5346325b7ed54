"""A layer rerun publishes its files and its evidence together (#27): `deformsmith physical | material | manipulate
DIR` failing or killed at any point leaves the asset directory as it was, evidence/attempts.jsonl included.

Default: the publish step itself (tasks.publish.staged_update) with a failure injected at each point, a SIGKILL'd
writer, and each layer command with its layer stood in by one that starts writing (through the real evidence writer,
tasks.agents.records.AttemptRecorder, which drops the stage's old lines) and then fails. Slow: the real L1 and L2
reruns, SIGKILL'd mid-run and failing at their last write, then `deformsmith evidence` read against the documents.
"""

from __future__ import annotations

import errno
import hashlib
import os
import signal
import subprocess
import sys
import textwrap
from collections.abc import Callable
from pathlib import Path

import pytest

from contracts.evidence import AgentSource, Attempt
from tasks import publish

REPO = Path(__file__).resolve().parents[2]
BIG_BYTES = 2 << 20  # a recording large enough to be hard-linked into a working copy (tasks.publish.COPY_BELOW_BYTES)


def tree_digest(root: Path) -> dict[str, str]:
    """Every file under `root` (relative path -> sha256), symbolic links by target."""
    out = {}
    for p in sorted(root.rglob("*")):
        rel = str(p.relative_to(root))
        if p.is_symlink():
            out[rel] = "link:" + os.readlink(p)
        elif p.is_file():
            out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
        else:
            out[rel] = "dir"
    return out


def _attempt(stage: str, iteration: int = 0, verdict: str = "accepted") -> str:
    return Attempt(stage=stage, iteration=iteration, action="propose", proposal={"x": 1.0}, source=AgentSource(),
                   verdict=verdict, score=1.0).model_dump_json() + "\n"


def make_asset(root: Path) -> Path:
    """A stand-in asset directory with L0, L1, L2 and L3 documents, evidence and a large (hard-linked) recording."""
    a = root / "sponge"
    for rel, data in {
        "geometry.json": '{"stand_in": true}\n', "physical.json": '{"passed": true, "old": 1}\n',
        "material.json": '{"passed": true, "old": 2}\n', "manipulation.json": '{"passed": true, "old": 3}\n',
        "evidence/attempts.jsonl": _attempt("L1") + _attempt("L2") + _attempt("L3"),
        "evidence/L2_attempts.jsonl": _attempt("L2"), "evidence/L1_outcome.json": '{"status": "accepted"}\n',
        "particles.zarr/positions_m/c/0/0": "chunk",
    }.items():
        (a / rel).parent.mkdir(parents=True, exist_ok=True)
        (a / rel).write_text(data)
    (a / "recordings").mkdir()
    (a / "recordings" / "L1_place.rrd").write_bytes(os.urandom(BIG_BYTES))
    os.symlink("physical.json", a / "link_to_physical")
    return a


def partials(parent: Path) -> list[str]:
    return [p.name for p in parent.iterdir() if ".partial-" in p.name or ".old-" in p.name]


# -- the publish step ------------------------------------------------------------------------------------------------
def test_staged_update_publishes_the_new_files_and_evidence_together(tmp_path: Path) -> None:
    assert BIG_BYTES > publish.COPY_BELOW_BYTES
    asset = make_asset(tmp_path)
    big_inode = (asset / "recordings" / "L1_place.rrd").stat().st_ino
    with publish.staged_update(asset) as work:
        assert work.parent == asset.parent and work != asset
        assert tree_digest(work) == tree_digest(asset)  # a full working copy
        assert (work / "recordings" / "L1_place.rrd").stat().st_ino == big_inode  # large files are hard links
        assert (work / "evidence" / "attempts.jsonl").stat().st_ino != (asset / "evidence" / "attempts.jsonl").stat().st_ino
        publish.write_text_atomic(work / "physical.json", '{"new": 1}\n')
        publish.write_text_atomic(work / "evidence" / "attempts.jsonl", _attempt("L2") + _attempt("L3") + _attempt("L1", 1))
        assert (asset / "physical.json").read_text() == '{"passed": true, "old": 1}\n'  # nothing visible yet
    assert (asset / "physical.json").read_text() == '{"new": 1}\n'
    assert (asset / "evidence" / "attempts.jsonl").read_text().count('"L1"') == 1
    assert (asset / "recordings" / "L1_place.rrd").stat().st_ino == big_inode
    assert partials(tmp_path) == []


@pytest.mark.parametrize("where", ["in_the_layer", "at_the_swap", "swap_without_exchange"])
def test_a_failure_at_any_point_of_the_publish_leaves_the_asset_as_it_was(where: str, tmp_path: Path,
                                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    asset = make_asset(tmp_path)
    before = tree_digest(asset)

    def full(*args: object) -> bool:
        raise OSError(errno.ENOSPC, "No space left on device", str(asset))

    if where == "at_the_swap":
        monkeypatch.setattr(publish, "exchange_directories", full)
    elif where == "swap_without_exchange":  # the two-rename fallback, failing at its second rename
        monkeypatch.setattr(publish, "exchange_directories", lambda a, b: False)
        real_replace, calls = os.replace, []

        def replace(src: object, dst: object) -> None:
            calls.append(dst)
            if len(calls) == 2:
                raise OSError(errno.ENOSPC, "No space left on device", str(dst))
            real_replace(src, dst)  # type: ignore[arg-type]

        monkeypatch.setattr(publish.os, "replace", replace)
    with pytest.raises(OSError, match="No space"):
        with publish.staged_update(asset) as work:
            (work / "physical.json").write_text('{"half')  # a half-written document (a copy: not the asset's)
            (work / "evidence" / "attempts.jsonl").write_text("")  # evidence truncated, as the finding saw it
            if where == "in_the_layer":
                raise OSError(errno.ENOSPC, "No space left on device", str(work / "material.json"))
    monkeypatch.undo()
    assert tree_digest(asset) == before
    assert partials(tmp_path) == []


def test_the_fallback_without_an_atomic_exchange_publishes_too(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    asset = make_asset(tmp_path)
    monkeypatch.setattr(publish, "exchange_directories", lambda a, b: False)
    with publish.staged_update(asset) as work:
        publish.write_text_atomic(work / "material.json", "{}\n")
    assert (asset / "material.json").read_text() == "{}\n" and partials(tmp_path) == []


def test_an_asset_reached_through_a_link_is_updated_where_it_lies(tmp_path: Path) -> None:
    asset = make_asset(tmp_path)
    (tmp_path / "elsewhere").mkdir()
    link = tmp_path / "elsewhere" / "sponge"
    os.symlink(asset, link)
    with publish.staged_update(link) as work:
        publish.write_text_atomic(work / "material.json", "{}\n")
    assert link.is_symlink() and (asset / "material.json").read_text() == "{}\n"
    assert partials(tmp_path) == [] and partials(tmp_path / "elsewhere") == []


def test_an_error_in_the_working_copy_names_the_asset_path(tmp_path: Path) -> None:
    asset = make_asset(tmp_path)
    with pytest.raises(OSError) as info:
        with publish.staged_update(asset) as work:
            raise OSError(errno.ENOSPC, "No space left on device", str(work / "evidence" / "attempts.jsonl"))
    assert info.value.filename == str(asset.absolute() / "evidence" / "attempts.jsonl")


_KILLED_WRITER = """
import os, signal, sys
from pathlib import Path
from tasks.publish import staged_update
with staged_update(Path(sys.argv[1])) as work:
    (work / "physical.json").write_text('{"half')
    (work / "evidence" / "attempts.jsonl").write_text("")
    os.kill(os.getpid(), signal.SIGKILL)
"""


def test_a_sigkilled_publish_leaves_the_asset_and_the_next_one_cleans_up(tmp_path: Path) -> None:
    asset = make_asset(tmp_path)
    before = tree_digest(asset)
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(_KILLED_WRITER), str(asset)], cwd=REPO,
                          capture_output=True, text=True, timeout=60, env={**os.environ, "PYTHONPATH": str(REPO)})
    assert proc.returncode == -signal.SIGKILL, proc.stderr[-2000:]
    assert tree_digest(asset) == before
    assert len(partials(tmp_path)) == 1  # the dead writer's working copy, beside the asset
    with publish.staged_update(asset):
        pass
    assert tree_digest(asset) == before and partials(tmp_path) == []


# -- the layer commands ----------------------------------------------------------------------------------------------
def _failing_layer(stage: str, document: str, exc: BaseException) -> Callable[..., object]:
    """A layer that starts publishing as the real ones do (the harness's evidence writer drops the stage's old lines
    and appends the new attempt; the document and the recording are rewritten) and then fails with `exc`."""
    def run(asset_dir: Path, *args: object, **kwargs: object) -> object:
        from tasks.agents.records import AttemptRecorder

        rec = AttemptRecorder(asset_dir, stage, rrd=False)
        rec.record(Attempt.model_validate_json(_attempt(stage, 0, "revise")))
        (Path(asset_dir) / document).write_text('{"passed": tr')
        (Path(asset_dir) / "recordings" / "L1_place.rrd").unlink()
        (Path(asset_dir) / "recordings" / "L1_place.rrd").write_bytes(b"new")
        raise exc

    return run


LAYERS = [  # command, the flow module and its entry point, stage, document
    ("physical", "flows.l1_physical", "run_l1", "L1", "physical.json"),
    ("material", "flows.l2_material", "run_l2", "L2", "material.json"),
    ("manipulate", "flows.l3_manipulation", "run_l3", "L3", "manipulation.json"),
]


@pytest.mark.parametrize("command, module, entry, stage, document", LAYERS, ids=[x[0] for x in LAYERS])
def test_a_layer_command_failing_mid_layer_leaves_the_asset_and_its_evidence(
        command: str, module: str, entry: str, stage: str, document: str, tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib

    from typer.testing import CliRunner

    from flows.cli.main import app

    asset = make_asset(tmp_path)
    before = tree_digest(asset)
    full = OSError(errno.ENOSPC, "No space left on device", "?")
    monkeypatch.setattr(importlib.import_module(module), entry, _failing_layer(stage, document, full))
    result = CliRunner().invoke(app, [command, str(asset)])
    assert result.exit_code != 0
    assert isinstance(result.exception, OSError) and result.exception.errno == errno.ENOSPC, result.output
    assert tree_digest(asset) == before  # physical.json and its evidence, both as they were
    assert partials(tmp_path) == []
