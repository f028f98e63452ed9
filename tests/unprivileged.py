"""Run a function in a forked child as an unprivileged user (root reads and enters
everything, so permission errors can only be seen without root's rights)."""
from __future__ import annotations

import json
import os
from typing import Any, Callable

NOBODY = 65534


def call_unprivileged(fn: Callable[[], Any]) -> Any:
    """``fn()`` evaluated in a forked child that runs as user and group nobody when we are
    root (as ourselves otherwise); returns its JSON-serialisable result, or raises
    RuntimeError with the child's exception."""
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # child: never returns into pytest
        os.close(read_end)
        try:
            if os.geteuid() == 0:
                os.setgroups([])
                os.setgid(NOBODY)
                os.setuid(NOBODY)
            payload = {"result": fn()}
        except BaseException as exc:  # noqa: BLE001 - reported to the parent
            payload = {"error": f"{type(exc).__name__}: {exc}"}
        with os.fdopen(write_end, "w") as fh:
            json.dump(payload, fh)
        os._exit(0)
    os.close(write_end)
    with os.fdopen(read_end) as fh:
        text = fh.read()
    os.waitpid(pid, 0)
    payload = json.loads(text)
    if "error" in payload:
        raise RuntimeError(payload["error"])
    return payload["result"]
