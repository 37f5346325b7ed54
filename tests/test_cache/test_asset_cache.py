"""A fully cached `generate` is served from the request's published asset in the cache (tasks.asset_cache): same
request, options and code -> republished, no layer and no Prefect server; any changed input, option, code or data file
misses, and the layers run (their cached tasks re-run exactly what depends on the change)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from cache import CacheStore, cache_root
from contracts.manifest import AssetManifest, Provenance, StageSummary
from contracts.request import AssetRequest
from tasks import asset_cache
from tasks.record.fingerprint import content_fingerprint

TEXT = "a soft plush turtle toy, about 25 cm long"
OPTIONS = {"device": "cpu", "cpu_threads": 2, "keep": "adopted", "manipulate": True}


def _key(request: AssetRequest | None = None, **changes: object) -> str | None:
    return asset_cache.request_key(request or AssetRequest(text=TEXT), **{**OPTIONS, **changes})  # type: ignore[arg-type]


def test_the_fingerprint_changes_with_every_input_option_and_the_code(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    base = _key()
    assert base is not None and base == _key()  # stable
    others = [
        _key(AssetRequest(text="a soft plush turtle toy, about 26 cm long")),
        _key(AssetRequest(text=TEXT, seed=1)),
        _key(AssetRequest(text=TEXT, quality="standard")),
        _key(AssetRequest(text=TEXT, size_hint_m=0.3)),
        _key(AssetRequest(text=TEXT, material_intent="firm rubber")),
        _key(AssetRequest(text=TEXT, pose="stable")),
        _key(device="cuda"), _key(cpu_threads=1), _key(keep="all"), _key(manipulate=False),
    ]
    assert len({base, *others}) == len(others) + 1
    mesh = tmp_path / "m.obj"
    mesh.write_text("v 0 0 0\n")
    with_mesh = _key(AssetRequest(mesh_path=mesh))
    mesh.write_text("v 0 0 1\n")  # the same path, other bytes
    assert with_mesh is not None and _key(AssetRequest(mesh_path=mesh)) not in (None, with_mesh)
    versions = asset_cache.library_versions()
    monkeypatch.setattr(asset_cache, "library_versions", lambda: {**versions, "warp-lang": "0.0.0"})
    assert _key() != base  # another library version: asset.json's provenance would differ
    monkeypatch.setattr(asset_cache, "code_fingerprint", lambda root=None: "another code")
    assert _key() not in (None, base)


def test_no_fingerprint_where_something_outside_decides_the_result(monkeypatch: pytest.MonkeyPatch) -> None:
    assert _key(llm="openai/gpt-4o-mini") is None
    assert _key(AssetRequest(text=TEXT, geometry_backend="mod:fn")) is None
    monkeypatch.setenv("PREFECT_API_URL", "http://prefect.example:4200/api")  # the user's server records the runs
    assert _key() is None
    monkeypatch.setenv("DEFORMSMITH_LOCAL_PREFECT_API", "http://prefect.example:4200/api")  # one DeformSmith started
    assert _key() is not None


def test_the_code_fingerprint_reads_every_code_and_data_file_not_byte_code(tmp_path: Path) -> None:
    for top in asset_cache.CODE_DIRS:
        (tmp_path / top / "__pycache__").mkdir(parents=True)
        (tmp_path / top / "mod.py").write_text("x = 1\n")
    (tmp_path / "contracts" / "lexicon.yaml").write_text("turtle: {}\n")
    base = asset_cache.code_fingerprint(tmp_path)
    (tmp_path / "tasks" / "__pycache__" / "mod.cpython-311.pyc").write_bytes(b"\0")
    (tmp_path / "out").mkdir()  # outside the package
    assert asset_cache.code_fingerprint(tmp_path) == base
    (tmp_path / "contracts" / "lexicon.yaml").write_text("turtle: {mass: 1}\n")
    assert asset_cache.code_fingerprint(tmp_path) != base
    assert asset_cache.code_fingerprint() == asset_cache.code_fingerprint()  # this checkout's: stable


def _asset(path: Path, named: list[str] = ()) -> Path:  # type: ignore[assignment]
    """A published asset directory: asset.json, a binary file, records naming cache entries and recordings."""
    path.mkdir(parents=True)
    manifest = AssetManifest(request=AssetRequest(text=TEXT), provenance=Provenance(deformsmith_version="t"),
                             validation=[StageSummary(stage="L0", passed=True, attempts=1, sim_calls=0)])
    (path / "asset.json").write_text(manifest.model_dump_json(indent=1))
    (path / "mesh.glb").write_bytes(os.urandom(4096))
    (path / "evidence").mkdir()
    (path / "manipulation.json").write_text(json.dumps({"attempts": [{"data_key": k} for k in named]}))
    return path


def test_a_kept_asset_is_served_equal_by_content_and_not_once_something_it_names_is_gone(tmp_path: Path) -> None:
    store = CacheStore(cache_root())
    store.put("ab" * 32, {"x": 1})  # a trial the asset leaves in the cache
    (store.root / "recordings").mkdir()
    (store.root / "recordings" / "L2_drop-0123456789abcdef.rrd").write_bytes(b"rrd")
    asset = _asset(tmp_path / "made", ["ab" * 32, "cd" * 32])  # "cd..." is no entry: not a reference
    (asset / "material.json").write_text(json.dumps({"cached_recordings": ["recordings/L2_drop-0123456789abcdef.rrd",
                                                                           "recordings/L2_lift-ffffffffffffffff.rrd"]}))
    key = "ef" * 32
    assert asset_cache.keep_asset(key, asset, "built by analogy: a tenrec")
    assert not asset_cache.keep_asset(key, asset, None)  # kept once
    value = store.get(key)
    assert value["references"] == ["ab" * 32, "recordings/L2_drop-0123456789abcdef.rrd"]

    out = tmp_path / "out" / "asset"
    served = asset_cache.serve(key, out)
    assert served is not None and served.analogy == "built by analogy: a tenrec"
    assert content_fingerprint(out) == content_fingerprint(asset)
    assert store.events()[-1]["task"] == asset_cache.TASK and store.events()[-1]["outcome"] == "hit"
    assert not [p for p in out.parent.iterdir() if p.name != "asset"]  # no working directory left
    assert asset_cache.serve(key, tmp_path / "strict", strict_concept=True) is None  # --strict-concept refuses it
    assert not (tmp_path / "strict").exists()
    assert asset_cache.serve("01" * 32, tmp_path / "none") is None

    (store.root / "recordings" / "L2_drop-0123456789abcdef.rrd").unlink()  # cache gc took a recording it names
    assert asset_cache.serve(key, tmp_path / "gone") is None and not (tmp_path / "gone").exists()


def test_a_corrupt_kept_asset_is_not_served(tmp_path: Path) -> None:
    key = "ef" * 32
    assert asset_cache.keep_asset(key, _asset(tmp_path / "made"), None)
    stored = next((CacheStore(cache_root()).entry_dir(key) / "_files").rglob("mesh.glb"))
    stored.write_bytes(b"edited")  # e.g. a hard link someone wrote through
    assert asset_cache.serve(key, tmp_path / "out") is None and not (tmp_path / "out").exists()


class _FakeLayers:
    """flows.generate.generate_asset standing in for the layers: publishes a small asset, counts its calls."""

    def __init__(self) -> None:
        self.calls: list[AssetRequest] = []

    def __call__(self, checked, out, **kwargs):  # noqa: ANN001, ANN003, ANN204
        import shutil

        self.calls.append(checked.request)
        kwargs["on_stage"]("L2", "warning: no material named in 'x': using the default material's target bands")
        out = Path(out)
        if out.exists():
            shutil.rmtree(out)
        _asset(out, [])
        return AssetManifest.model_validate_json((out / "asset.json").read_text())


@pytest.fixture
def cli(monkeypatch: pytest.MonkeyPatch) -> tuple[_FakeLayers, list[int]]:
    import flows.cli.generate_cmds as cmds
    import flows.generate as gen
    from cache import runtime

    layers = _FakeLayers()
    servers: list[int] = []
    monkeypatch.setattr(gen, "generate_asset", layers)
    monkeypatch.setattr(runtime, "prestart_local_server", lambda: servers.append(1))
    monkeypatch.setattr(cmds, "concept_line", lambda request, strict: None)  # (L0's parse: not what is tested)
    return layers, servers


def _generate(*args: str) -> str:
    from flows.cli.main import app

    res = CliRunner().invoke(app, ["generate", *args])
    assert res.exit_code == 0, res.output
    return res.output if "--json" not in args else res.stdout


def test_a_rerun_is_served_without_the_layers_or_a_server_and_a_changed_input_is_not(
        tmp_path: Path, cli: tuple[_FakeLayers, list[int]], monkeypatch: pytest.MonkeyPatch) -> None:
    layers, servers = cli
    out = tmp_path / "turtle"
    first = _generate(TEXT, "--out", str(out))
    assert len(layers.calls) == 1 and servers == [1] and "asset published" in first
    made = content_fingerprint(out)
    rerun = _generate(TEXT, "--out", str(out))
    assert len(layers.calls) == 1 and servers == [1], "the rerun ran the layers"
    assert "republished from the result cache" in rerun and "asset published" in rerun
    assert "warning: no material named" in " ".join(rerun.split())  # the warnings of the run that made it, again
    assert content_fingerprint(out) == made
    _generate(TEXT, "--out", str(tmp_path / "elsewhere"))  # another output folder: the same asset, served
    assert len(layers.calls) == 1 and content_fingerprint(tmp_path / "elsewhere") == made

    for changed in (["--seed", "1"], ["--no-l3"], ["--record", "all"], ["--cpu-threads", "1"], ["--size-m", "0.3"],
                    ["--intent", "firm rubber"], ["--quality", "standard"]):
        before = len(layers.calls)
        _generate(TEXT, "--out", str(out), *changed)
        assert len(layers.calls) == before + 1, f"{changed} was served from the cache"
    before = len(layers.calls)
    _generate(TEXT + ".", "--out", str(out))  # another text
    assert len(layers.calls) == before + 1

    monkeypatch.setattr(asset_cache, "code_fingerprint", lambda root=None: "the code changed")
    before = len(layers.calls)
    _generate(TEXT, "--out", str(out))
    assert len(layers.calls) == before + 1, "a code change was served from the cache"
    _generate(TEXT, "--out", str(out))  # and kept under the new code's fingerprint
    assert len(layers.calls) == before + 1


def test_a_served_rerun_prints_the_same_json_summary(
        tmp_path: Path, cli: tuple[_FakeLayers, list[int]]) -> None:
    layers, _ = cli
    out = tmp_path / "turtle"
    made = json.loads(_generate(TEXT, "--out", str(out), "--json"))
    served = json.loads(_generate(TEXT, "--out", str(out), "--json"))
    assert len(layers.calls) == 1
    assert {k: v for k, v in served.items() if k != "wall_time_s"} == {
        k: v for k, v in made.items() if k != "wall_time_s"}
    assert list(served["wall_time_s"]) == ["cache"]


def test_the_analogy_line_is_remembered_by_text_size_code_and_libraries(monkeypatch: pytest.MonkeyPatch) -> None:
    """generate's first line (tasks.preflight.concept_line) reads the words (~3 s of spaCy, lexicon and WordNet): a
    rerun with the same text, size and code reads it from the cache; any of them changed reads the words again."""
    import tasks.geometry.catalogue as catalogue
    from contracts.errors import InputError
    from tasks.preflight import concept_line

    read: list[str] = []
    real = catalogue.design_from_text

    def counting(text, size_hint_m=None, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN202
        read.append(text)
        return real(text, size_hint_m, *args, **kwargs)

    monkeypatch.setattr(catalogue, "design_from_text", counting)
    from cache import cache_root

    (cache_root() / "entries").mkdir(parents=True, exist_ok=True)  # a cache in use (an empty one is not made)
    tenrec = AssetRequest(text="a tenrec")
    line = concept_line(tenrec, False)
    assert line is not None and "tenrec" in line and len(read) == 1
    assert concept_line(tenrec, False) == line and len(read) == 1  # remembered
    with pytest.raises(InputError, match="--strict-concept"):
        concept_line(tenrec, True)  # refused from the remembered line as from a fresh one
    assert len(read) == 1
    assert concept_line(AssetRequest(text=TEXT), False) is None and len(read) == 2  # named by the lexicon: None
    assert concept_line(AssetRequest(text=TEXT), False) is None and len(read) == 2
    concept_line(AssetRequest(text="a tenrec", size_hint_m=0.2), False)  # another size
    assert len(read) == 3
    monkeypatch.setattr(asset_cache, "code_fingerprint", lambda root=None: "another lexicon")
    assert concept_line(tenrec, False) == line and len(read) == 4  # another code or data: read again
