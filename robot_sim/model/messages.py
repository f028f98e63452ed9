"""Error-message helpers: values quoted in a message are cut to a readable length."""
from __future__ import annotations

from typing import Any

#: Characters of a value kept in an error message; the rest is replaced by its length.
MESSAGE_VALUE_CHARS = 80


def clip(text: str, limit: int = MESSAGE_VALUE_CHARS) -> str:
    """``text`` itself if at most ``limit`` characters, else its first ``limit``
    characters followed by ``... (N characters)``."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


def clip_repr(value: Any, limit: int = MESSAGE_VALUE_CHARS) -> str:
    """``repr(value)`` cut by :func:`clip` (a 5 KB value echoes as about 100 characters).
    An integer too long for ``repr`` (over 4300 digits) is described by its size."""
    try:
        text = repr(value)
    except ValueError:
        return f"an integer of about {int(value.bit_length() * 0.30103)} digits"
    return clip(text, limit)


#: Characters of a file path kept in an error message (its start and its end).
MESSAGE_PATH_CHARS = 160


def clip_middle(text: str, limit: int = MESSAGE_PATH_CHARS) -> str:
    """``text`` itself if at most ``limit`` characters, else its start and end around
    ``...`` (``limit`` characters in all), so a long path keeps its file name."""
    if len(text) <= limit:
        return text
    head = limit // 4
    return f"{text[:head]}...{text[len(text) - (limit - head - 3):]}"
