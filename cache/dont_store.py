"""Results that must not be stored: a cached task whose answer is a stand-in (the rule backend answering for an LLM
that could not be reached) says so, and the store keeps nothing under that task's key; a later run computes again."""

from __future__ import annotations

import sys
import threading
from typing import Any

_MARKED: set[str] = set()
_LOCK = threading.Lock()


def dont_store() -> None:
    """Inside a cached task run: return its result but do not store it. Outside a task run: nothing."""
    if "prefect.context" not in sys.modules:  # Prefect never imported: certainly not inside a task run
        return
    from prefect.context import TaskRunContext

    ctx = TaskRunContext.get()
    if ctx is not None:
        with _LOCK:
            _MARKED.add(str(ctx.task_run.id))


def take_mark(task_run_id: Any) -> bool:
    """True (once) when the task run asked for its result not to be stored."""
    with _LOCK:
        if str(task_run_id) in _MARKED:
            _MARKED.discard(str(task_run_id))
            return True
    return False
