"""Single-key shortcuts reach the window from every widget that is not being edited.

The GL view passes the keys it does not use up to the main window, whose
``keyPressEvent`` looks them up in ``KEY_BINDINGS``.  Widgets that take the keyboard
focus for something else (the DH table after a click on a row, pyqtgraph's plot view)
would swallow them: an item view turns a letter into a search or, with an edit trigger,
into a cell edit nobody opened.  :class:`ShortcutFilter` sits on such widgets and hands
a bound key to the window unless the widget is editing (an item view with an open cell
editor keeps its keys: the editor is a separate text widget).
"""
from __future__ import annotations

from typing import Callable

from PyQt5 import QtCore, QtGui, QtWidgets


def is_editing(widget: QtWidgets.QWidget) -> bool:
    """True while ``widget`` is a text entry or an item view with an open cell editor."""
    if isinstance(widget, QtWidgets.QAbstractItemView):
        return widget.state() == QtWidgets.QAbstractItemView.EditingState
    return isinstance(widget, (QtWidgets.QLineEdit, QtWidgets.QAbstractSpinBox, QtWidgets.QTextEdit,
                               QtWidgets.QPlainTextEdit))


class ShortcutFilter(QtCore.QObject):
    """Event filter: a key press on a watched widget that is not editing and that
    ``is_bound`` recognises goes to ``dispatch`` instead of the widget."""

    def __init__(self, parent: QtCore.QObject, is_bound: Callable[[QtGui.QKeyEvent], bool],
                 dispatch: Callable[[QtGui.QKeyEvent], None]) -> None:
        super().__init__(parent)
        self.is_bound, self.dispatch = is_bound, dispatch

    def watch(self, *widgets: QtWidgets.QWidget) -> None:
        """Route the bound keys of ``widgets``."""
        for widget in widgets:
            widget.installEventFilter(self)

    def eventFilter(self, obj: QtCore.QObject, event: QtCore.QEvent) -> bool:  # noqa: N802 - Qt's name
        if event.type() != QtCore.QEvent.KeyPress or not isinstance(obj, QtWidgets.QWidget) or is_editing(obj):
            return False
        if not self.is_bound(event):
            return False
        self.dispatch(event)
        return True
