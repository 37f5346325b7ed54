"""`deformsmith probe` / `material`: invalid parameters end in one clear line and a non-zero exit."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from flows.cli.main import app


@pytest.fixture
def stub_asset(tmp_path: Path) -> Path:
    """A directory that looks like an asset (parameter checks come before any probe runs)."""
    d = tmp_path / "asset"
    d.mkdir()
    (d / "geometry.json").write_text(json.dumps({"files": {}}))
    return d


@pytest.mark.parametrize("args, needle", [
    (["--E", "-5"], "E (--E) [Pa] = -5.0"),
    (["--E", "0"], "E (--E) [Pa] = 0.0"),
    (["--nu", "0.5"], "nu (--nu) = 0.5"),
    (["--nu", "0.7"], "nu (--nu) = 0.7"),
    (["--E", "nan"], "--E must be a finite number"),
    (["--damping", "-1"], "damping (--damping)"),
])
def test_invalid_material_parameters_are_rejected(stub_asset: Path, args: list[str], needle: str) -> None:
    """E <= 0, nu >= 0.5, NaN, negative damping: exit code != 0 and one line naming the parameter."""
    res = CliRunner().invoke(app, ["probe", "compress", "--asset", str(stub_asset), *args, "--json"])
    assert res.exit_code != 0
    err = res.stderr if hasattr(res, "stderr") else res.output
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and needle in lines[0], err


def test_unknown_probe_and_missing_asset(tmp_path: Path, stub_asset: Path) -> None:
    """An unknown probe kind or a directory without L0 output is a clear error."""
    r1 = CliRunner().invoke(app, ["probe", "squash", "--asset", str(stub_asset)])
    assert r1.exit_code != 0 and "unknown probe 'squash'" in r1.output
    r2 = CliRunner().invoke(app, ["probe", "compress", "--asset", str(tmp_path / "nope"), "--E", "1e4"])
    assert r2.exit_code != 0 and "not an asset directory" in r2.output
    r3 = CliRunner().invoke(app, ["probe", "compress", "--asset", str(stub_asset), "--rho", "-3"])
    assert r3.exit_code != 0 and "--rho" in r3.output
