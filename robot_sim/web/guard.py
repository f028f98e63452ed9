"""No exception escapes a browser event handler: :func:`guarded` runs a handler under the
backend's lock and turns any exception into a line on the page's status (the server and
every other page carry on)."""
from __future__ import annotations

import functools
import traceback
from typing import Any, Callable, TypeVar

F = TypeVar("F", bound=Callable[..., Any])


def guarded(method: F) -> F:
    """Wrap a method of an object with ``lock`` and ``say(text)``: run it holding the lock;
    an exception becomes ``say("internal error in <handler>: <Type>: <message>")`` and is
    printed with its traceback on the server's stderr."""

    @functools.wraps(method)
    def run(self: Any, *args: Any, **kwargs: Any) -> Any:
        try:
            with self.lock:
                return method(self, *args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - the handler's failure must not reach viser's thread
            traceback.print_exc()
            try:
                self.say(f"internal error in {method.__name__}: {type(exc).__name__}: {str(exc)[:200]}")
            except Exception:  # noqa: BLE001 - the page may be gone
                traceback.print_exc()
            return None

    return run  # type: ignore[return-value]
