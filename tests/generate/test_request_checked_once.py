"""The request is checked once, at the boundary (#37): generate_asset checks a plain request once; a request the CLI
checked already (tasks.request.CheckedRequest) is not checked again by generate_asset nor by the generate flow."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import flows.generate as gen
import tasks.request as req
from contracts.errors import InputError
from contracts.request import AssetRequest


@pytest.fixture
def calls(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Every derivation of a request's targets, and a generate flow that only checks what it is handed."""
    seen: list[str] = []
    real = req.targets_from_request

    def counted(request: AssetRequest, *args: Any, **kwargs: Any) -> Any:
        seen.append(request.text or "")
        return real(request, *args, **kwargs)

    monkeypatch.setattr(req, "targets_from_request", counted)
    monkeypatch.setattr(gen, "generate", lambda checked, *a, **k: req.checked_request(checked))
    monkeypatch.setattr(gen.cache, "local_runtime", lambda: _Null())
    return seen


class _Null:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> None:
        return None


def test_a_plain_request_is_checked_once(calls: list[str], tmp_path: Path) -> None:
    checked = gen.generate_asset(AssetRequest(text="a soft foam cube 3 cm"), tmp_path / "a")
    assert isinstance(checked, req.CheckedRequest) and calls == ["a soft foam cube 3 cm"]


def test_a_checked_request_is_not_checked_again(calls: list[str], tmp_path: Path) -> None:
    checked = req.checked_request(AssetRequest(text="a soft foam cube 3 cm"))
    assert gen.generate_asset(checked, tmp_path / "a") is checked and len(calls) == 1  # the boundary's one check


def test_what_the_check_refuses_is_refused_before_any_flow(calls: list[str], tmp_path: Path) -> None:
    with pytest.raises(InputError):
        gen.generate_asset(AssetRequest(text="a steel cube 3 cm"), tmp_path / "a")  # a rigid material
    with pytest.raises(InputError):
        gen.generate_asset(AssetRequest(text="a foam cube 10 km long"), tmp_path / "b")
