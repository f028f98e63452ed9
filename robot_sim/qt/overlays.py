"""Widgets drawn over the window: the help overlay (key and mouse bindings) and the view
information in the GL view's bottom-left corner (grid scale, projection, follow mode).
The workspace cloud's colour scale is part of the picture (render_scene draws it, in the
window and in ``--screenshot`` alike).

Both are Qt widgets painted with QPainter above the GL picture, so they share no GL state
with the render path (``graphics.View``).
"""
from __future__ import annotations

import html
from dataclasses import dataclass

from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs


def help_rows() -> list[tuple[str, str]]:
    """(keys, description) rows from KEY_BINDINGS then MOUSE_BINDINGS; consecutive
    bindings with the same description share a row ("W / S", "1 .. 9")."""
    groups: list[tuple[list[str], str]] = []
    for key, mods, _action, _arg, text in qs.KEY_BINDINGS:
        name = f"{mods}+{key}" if mods else key
        if groups and groups[-1][1] == text:
            groups[-1][0].append(name)
        else:
            groups.append(([name], text))
    rows = [(" / ".join(names) if len(names) <= 2 else f"{names[0]} .. {names[-1]}", text) for names, text in groups]
    return rows + list(qs.MOUSE_BINDINGS)


def help_lines() -> list[str]:
    """The help rows as aligned text lines ("keys  description")."""
    rows = help_rows()
    width = max(len(name) for name, _ in rows)
    return [f"{name:<{width}}  {text}" for name, text in rows]


class HelpOverlay(QtWidgets.QScrollArea):
    """The key and mouse bindings over the 3D view, on a translucent dark panel.

    The rows are laid out in as many (keys, description) column pairs as fit the width
    (up to ``HELP_MAX_COLUMNS``); what does not fit the view scrolls, so the whole list
    is readable in any window from 640×480 up.  A click or Esc (handled by the window)
    closes it.
    """

    def __init__(self, parent: QtWidgets.QWidget) -> None:
        super().__init__(parent)
        self.setFocusPolicy(Qt.NoFocus)
        self.setFrameShape(QtWidgets.QFrame.NoFrame)
        self.setWidgetResizable(True)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarAsNeeded)  # a view narrower than one column
        self.setStyleSheet(
            "QScrollArea {background: transparent;}"
            " QLabel {color: rgb(%d, %d, %d);" % qs.HELP_TEXT_RGB
            + " background: rgba(%d, %d, %d, %d);}" % qs.HELP_BACKGROUND_RGBA
        )
        self.label = QtWidgets.QLabel()
        self.label.setTextFormat(Qt.RichText)
        self.label.setAlignment(Qt.AlignLeft | Qt.AlignTop)
        self.label.setMargin(qs.HELP_MARGIN_PX)
        font = QtGui.QFont(qs.HELP_FONT_FAMILY, qs.HELP_FONT_PT)
        font.setStyleHint(QtGui.QFont.TypeWriter)
        self.label.setFont(font)
        self.viewport().setAutoFillBackground(False)
        self.setWidget(self.label)
        self.columns = 0
        self.hide()

    def fit(self, area: QtCore.QRect) -> None:
        """Lay the rows out for ``area`` (the 3D view's rectangle) and take its
        top-left part: as much as the text needs, scrolling what is taller than ``area``."""
        scrollbar = self.verticalScrollBar().sizeHint().width()
        for columns in range(qs.HELP_MAX_COLUMNS, 0, -1):  # the most column pairs that fit
            self.columns = columns
            self.label.setText(self.table_html(columns))
            if self.label.sizeHint().width() + scrollbar <= area.width():
                break
        needed = self.label.sizeHint()
        width = min(area.width(), needed.width() + scrollbar)  # room for the bar if it shows
        height = needed.height() + (scrollbar if width < needed.width() + scrollbar else 0)  # and the sideways one
        self.setGeometry(area.left(), area.top(), width, min(area.height(), height))

    @staticmethod
    def table_html(columns: int) -> str:
        """The rows as an HTML table of ``columns`` (keys, description) pairs."""
        rows = help_rows()
        per_column = -(-len(rows) // columns)
        cell = f'style="padding-right: {qs.HELP_COLUMN_GAP_PX}px; white-space: pre"'
        lines = []
        for r in range(per_column):
            cells = []
            for c in range(columns):
                i = c * per_column + r
                keys, text = rows[i] if i < len(rows) else ("", "")
                cells.append(f"<td {cell}><b>{html.escape(keys)}</b></td><td {cell}>{html.escape(text)}</td>")
            lines.append("<tr>" + "".join(cells) + "</tr>")
        return "<table cellspacing=0>" + "".join(lines) + "</table>"

    def mousePressEvent(self, event: QtGui.QMouseEvent) -> None:
        self.hide()


@dataclass
class ViewInfo:
    """What the view's corner says: grid spacing (m), projection, follow mode."""

    grid_step: float
    orthographic: bool
    following: bool


class ViewInfoOverlay(QtWidgets.QWidget):
    """Bottom-left: grid spacing, projection and follow mode.  Transparent to the mouse."""

    def __init__(self, parent: QtWidgets.QWidget) -> None:
        super().__init__(parent)
        self.setAttribute(Qt.WA_TransparentForMouseEvents)
        self.setFocusPolicy(Qt.NoFocus)
        self.info = ViewInfo(grid_step=0.0, orthographic=False, following=False)

    def status_text(self) -> str:
        """The bottom-left line."""
        parts = [qs.VIEW_INFO_GRID_FORMAT.format(step=self.info.grid_step),
                 "orthographic" if self.info.orthographic else "perspective"]
        if self.info.following:
            parts.append("following the endeffector")
        return "  ·  ".join(parts)

    def paintEvent(self, event: QtGui.QPaintEvent) -> None:
        painter = QtGui.QPainter(self)
        font = painter.font()
        font.setPixelSize(qs.VIEW_INFO_TEXT_PX)
        painter.setFont(font)
        painter.setPen(QtGui.QColor(*qs.VIEW_INFO_TEXT_RGB))
        margin = qs.VIEW_INFO_MARGIN_PX
        painter.drawText(margin, self.height() - margin, self.status_text())
        painter.end()
