"""`deformsmith ARGS` run in the test's own process against the session's Prefect server (no interpreter start-up
per case): the real app stands in as a test's app, so the command returns here instead of ending the process
(flows.cli.main.main). A test that is about the process itself (signals, exit status as a shell sees it) runs the
command as a subprocess instead."""

from __future__ import annotations

import sys

import pytest


def cli_run(*args: str, api: str | None, monkeypatch: pytest.MonkeyPatch,
            capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    """(exit code, stdout, stderr) of `deformsmith ARGS`; `api`: the session's Prefect server (conftest's
    `prefect_api`), or None for a command that runs no flows (card, inspect, view: it starts no server either)."""
    from cache.runtime import local_api_env
    from flows.cli import main as cli_main
    from flows.cli.apps import app

    for key, value in (local_api_env(api) if api is not None else {}).items():
        monkeypatch.setenv(key, value)
    monkeypatch.setattr(cli_main, "app", app, raising=False)
    monkeypatch.setattr(sys, "argv", ["deformsmith", *args])
    capsys.readouterr()
    code: object = 0
    try:
        cli_main.main()
    except SystemExit as exc:
        code = exc.code or 0
    out = capsys.readouterr()
    return int(code), out.out, out.err  # type: ignore[call-overload]


def cli_in_process(*args: str, api: str | None, monkeypatch: pytest.MonkeyPatch,
                   capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """(exit code, stderr) of `deformsmith ARGS`."""
    code, _, err = cli_run(*args, api=api, monkeypatch=monkeypatch, capsys=capsys)
    return code, err
