"""The boundary between Qt and our code: no exception may escape a Qt event handler,
paint or slot (PyQt5 aborts the process when one does).

:func:`guarded` wraps a handler so that an exception is reported instead: printed with its
traceback on stderr (for the developer) and shown in the window's status bar through the
widget's ``report_error(text)`` (or its top-level window's), and the program keeps
running.  :func:`install_excepthook` is the safety net for handlers that are not wrapped:
PyQt5 calls ``sys.excepthook`` instead of aborting once it has been replaced.

This module does not import Qt: it only calls ``report_error`` and ``window()``.
"""
from __future__ import annotations

import functools
import sys
import traceback
from types import TracebackType
from typing import Any, Callable, TypeVar

from robot_sim.model.messages import clip

F = TypeVar("F", bound=Callable[..., Any])

#: Characters of an exception's message shown in the status bar.
ERROR_TEXT_CHARS = 200


def error_text(where: str, exc: BaseException) -> str:
    """One status-bar line for ``exc`` raised in ``where``."""
    message = " ".join(str(exc).split())
    return f"error in {where}: {type(exc).__name__}: {clip(message, ERROR_TEXT_CHARS)}"


def report(widget: Any, where: str, exc: BaseException) -> None:
    """Print ``exc`` with its traceback on stderr and show it through ``report_error`` of
    ``widget`` or of its top-level window.  Never raises."""
    try:
        traceback.print_exception(type(exc), exc, exc.__traceback__, file=sys.stderr)
        target = widget if hasattr(widget, "report_error") else widget.window()
        target.report_error(error_text(where, exc))
    except Exception:  # noqa: BLE001 - reporting must not become a new escape
        pass


def guarded(method: F) -> F:
    """Decorate a Qt event handler, paint or slot method: an exception it raises is
    reported (:func:`report`) and the handler returns None."""

    @functools.wraps(method)
    def wrapper(self: Any, *args: Any, **kwargs: Any) -> Any:
        try:
            return method(self, *args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - the Qt boundary
            report(self, method.__qualname__, exc)
            return None

    return wrapper  # type: ignore[return-value]


def install_excepthook(window: Any) -> Callable[..., Any]:
    """Make ``sys.excepthook`` report to ``window`` (see :func:`report`) so an exception
    in any handler that :func:`guarded` does not cover leaves the window running.
    Returns the previous hook."""
    previous = sys.excepthook

    def hook(kind: type[BaseException], exc: BaseException, tb: TracebackType | None) -> None:
        if not isinstance(exc, Exception):  # KeyboardInterrupt, SystemExit: as before
            previous(kind, exc, tb)
            return
        report(window, "a Qt handler", exc.with_traceback(tb))

    sys.excepthook = hook
    return previous
