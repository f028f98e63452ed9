"""Keys of the window: KEY_BINDINGS rows (robot_sim.qt.settings) as Qt key codes and
modifier bits, and the lookup of a key press."""
from __future__ import annotations

import functools
from typing import Any

from PyQt5 import QtGui
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs

_MODIFIER_FLAGS = {"Shift": Qt.ShiftModifier, "Ctrl": Qt.ControlModifier, "Alt": Qt.AltModifier}
_MODIFIER_MASK = int(functools.reduce(lambda a, b: a | b, _MODIFIER_FLAGS.values()))


def key_of(key: str, mods: str) -> tuple[int, int]:
    """(Qt key code, modifier bits) of a KEY_BINDINGS row's key name and modifiers."""
    bits = functools.reduce(lambda a, b: a | b, (_MODIFIER_FLAGS[m] for m in mods.split("+") if m), Qt.NoModifier)
    return int(getattr(Qt, f"Key_{key}")), int(bits)


#: (key code, modifier bits) -> (action, argument) of every KEY_BINDINGS row.
KEY_TABLE = {key_of(key, mods): (action, arg) for key, mods, action, arg, _ in qs.KEY_BINDINGS}


def binding(event: QtGui.QKeyEvent) -> tuple[str, Any] | None:
    """The (action, argument) bound to ``event``'s key and modifiers, or None."""
    return KEY_TABLE.get((int(event.key()), int(event.modifiers()) & _MODIFIER_MASK))
