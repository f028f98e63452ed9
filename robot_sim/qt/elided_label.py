"""A one-line label that fits any width: text too long for it ends in "…".

The status bar's one-off message and its permanent readout share the window's width; a
long IK or tracking report ran past the window's edge.  :class:`ElidedLabel` asks for
its text's width but accepts any, shows as much as fits, and keeps the whole text in
``text()`` and in its tooltip.
"""
from __future__ import annotations

from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt


class ElidedLabel(QtWidgets.QLabel):
    """A QLabel that elides its one line of text to its width (the full text in the
    tooltip): at the end, or with ``mode=Qt.ElideMiddle`` in the middle (a file path keeps
    its file name)."""

    def __init__(self, text: str = "", mode: Qt.TextElideMode = Qt.ElideRight) -> None:
        super().__init__()
        self.mode = mode
        self.setText(text)

    def setText(self, text: str) -> None:  # noqa: N802 - Qt's name
        super().setText(text)
        self.setToolTip(text)

    def minimumSizeHint(self) -> QtCore.QSize:  # noqa: N802 - Qt's name
        return QtCore.QSize(0, super().minimumSizeHint().height())

    def shown_text(self) -> str:
        """What fits: the text, or its start (and end) around "…"."""
        return self.fontMetrics().elidedText(self.text(), self.mode, self.contentsRect().width())

    def paintEvent(self, event: QtGui.QPaintEvent) -> None:  # noqa: N802 - Qt's name
        painter = QtGui.QPainter(self)
        painter.drawText(self.contentsRect(), int(self.alignment() | Qt.AlignVCenter), self.shown_text())
        painter.end()
