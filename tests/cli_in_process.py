"""`deformsmith ARGS` run in the test's own process against the session's Prefect server (no interpreter start-up
per case): the real app stands in as a test's app, so the command returns here instead of ending the process
(flows.cli.main.main). A test that is about the process itself (signals, exit status as a shell sees it) runs the
command as a subprocess instead."""

from __future__ import annotations

import sys

import pytest


def cli_in_process(*args: str, api: str, monkeypatch: pytest.MonkeyPatch,
                   capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """(exit code, stderr) of `deformsmith ARGS`."""
    from cache.runtime import local_api_env
    from flows.cli import main as cli_main
    from flows.cli.apps import app

    for key, value in local_api_env(api).items():
        monkeypatch.setenv(key, value)
    monkeypatch.setattr(cli_main, "app", app, raising=False)
    monkeypatch.setattr(sys, "argv", ["deformsmith", *args])
    capsys.readouterr()
    code: object = 0
    try:
        cli_main.main()
    except SystemExit as exc:
        code = exc.code or 0
    return int(code), capsys.readouterr().err  # type: ignore[call-overload]
