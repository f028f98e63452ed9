"""Framebuffers the render path draws into besides the host's: a multisampled colour and
depth target resolved into the host's framebuffer (anti-aliasing in the Qt widget and in
OSMesa alike), and the shadow map's depth texture.

Both are built in the current context on first use, resized on demand, and deleted with
:meth:`delete` while their context is current.
"""
from __future__ import annotations

from robot_sim.graphics.gl import GL


def _check_complete(what: str) -> None:
    status = GL.glCheckFramebufferStatus(GL.GL_FRAMEBUFFER)
    if status != GL.GL_FRAMEBUFFER_COMPLETE:
        raise RuntimeError(f"{what}: framebuffer incomplete (status 0x{int(status):x})")


def max_samples() -> int:
    """The largest sample count the current context's renderbuffers support."""
    return int(GL.glGetIntegerv(GL.GL_MAX_SAMPLES))


class MultisampleTarget:
    """A ``samples``-times multisampled framebuffer (RGBA8 colour, 24-bit depth).

    :meth:`begin` binds it for drawing at ``width`` x ``height`` and remembers the
    framebuffer that was bound (the host's: OSMesa's buffer or the Qt widget's FBO);
    :meth:`end` resolves the samples into that framebuffer and binds it again.
    """

    def __init__(self, samples: int) -> None:
        self.samples = int(samples)
        self._fbo = 0
        self._buffers: tuple[int, int] = (0, 0)
        self._size = (0, 0)
        self._host = 0

    def _build(self, width: int, height: int) -> None:
        self.delete()
        self._fbo = int(GL.glGenFramebuffers(1))
        color, depth = (int(b) for b in GL.glGenRenderbuffers(2))
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._fbo)
        for buffer, fmt, attachment in ((color, GL.GL_RGBA8, GL.GL_COLOR_ATTACHMENT0),
                                        (depth, GL.GL_DEPTH_COMPONENT24, GL.GL_DEPTH_ATTACHMENT)):
            GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, buffer)
            GL.glRenderbufferStorageMultisample(GL.GL_RENDERBUFFER, self.samples, fmt, width, height)
            GL.glFramebufferRenderbuffer(GL.GL_FRAMEBUFFER, attachment, GL.GL_RENDERBUFFER, buffer)
        GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, 0)
        _check_complete(f"{self.samples}x multisample target {width}x{height}")
        self._buffers, self._size = (color, depth), (width, height)

    def begin(self, width: int, height: int) -> None:
        """Bind the target (rebuilt when the size changed) for a ``width`` x ``height``
        frame, remembering the framebuffer bound before (where :meth:`end` resolves to)."""
        self._host = int(GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING))
        self.bind(width, height)

    def bind(self, width: int, height: int) -> None:
        """Bind the target for drawing, rebuilt when its size is not ``width`` x ``height``."""
        if self._size != (width, height) or not self._fbo:
            self._build(width, height)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._fbo)

    def end(self) -> None:
        """Resolve the samples into the host framebuffer and bind that again."""
        width, height = self._size
        GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, self._fbo)
        GL.glBindFramebuffer(GL.GL_DRAW_FRAMEBUFFER, self._host)
        GL.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL.GL_COLOR_BUFFER_BIT, GL.GL_NEAREST)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._host)

    def copy_from(self, other: MultisampleTarget) -> None:
        """Copy the colour and depth samples of ``other`` (same samples and size) into
        this target, which stays bound (cheaper on llvmpipe than clearing them)."""
        width, height = self._size
        GL.glBindFramebuffer(GL.GL_READ_FRAMEBUFFER, other._fbo)
        GL.glBindFramebuffer(GL.GL_DRAW_FRAMEBUFFER, self._fbo)
        GL.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height,
                             GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT, GL.GL_NEAREST)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._fbo)

    def delete(self) -> None:
        """Delete the framebuffer and its renderbuffers (their context must be current)."""
        if self._fbo:
            GL.glDeleteFramebuffers(1, [self._fbo])
            GL.glDeleteRenderbuffers(2, list(self._buffers))
        self._fbo, self._buffers, self._size = 0, (0, 0), (0, 0)


class ShadowTarget:
    """The shadow map: a ``size`` x ``size`` depth texture (compared on lookup, linearly
    filtered) attached to a framebuffer without colour."""

    def __init__(self, size: int) -> None:
        self.size = int(size)
        self.texture = 0
        self._fbo = 0

    def _build(self) -> None:
        self.texture = int(GL.glGenTextures(1))
        GL.glBindTexture(GL.GL_TEXTURE_2D, self.texture)
        GL.glTexImage2D(GL.GL_TEXTURE_2D, 0, GL.GL_DEPTH_COMPONENT24, self.size, self.size, 0,
                        GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT, None)
        for key, value in ((GL.GL_TEXTURE_MIN_FILTER, GL.GL_LINEAR), (GL.GL_TEXTURE_MAG_FILTER, GL.GL_LINEAR),
                           (GL.GL_TEXTURE_WRAP_S, GL.GL_CLAMP_TO_EDGE), (GL.GL_TEXTURE_WRAP_T, GL.GL_CLAMP_TO_EDGE),
                           (GL.GL_TEXTURE_COMPARE_MODE, GL.GL_COMPARE_REF_TO_TEXTURE),
                           (GL.GL_TEXTURE_COMPARE_FUNC, GL.GL_LEQUAL)):
            GL.glTexParameteri(GL.GL_TEXTURE_2D, key, value)
        GL.glBindTexture(GL.GL_TEXTURE_2D, 0)
        self._fbo = int(GL.glGenFramebuffers(1))
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._fbo)
        GL.glFramebufferTexture2D(GL.GL_FRAMEBUFFER, GL.GL_DEPTH_ATTACHMENT, GL.GL_TEXTURE_2D, self.texture, 0)
        GL.glDrawBuffer(GL.GL_NONE)
        GL.glReadBuffer(GL.GL_NONE)
        _check_complete(f"shadow map {self.size}x{self.size}")

    def begin(self) -> int:
        """Bind the shadow framebuffer with a cleared depth and its viewport; returns the
        framebuffer that was bound before (for :meth:`end`)."""
        previous = int(GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING))
        if not self._fbo:
            self._build()
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self._fbo)
        GL.glViewport(0, 0, self.size, self.size)
        GL.glDepthMask(GL.GL_TRUE)
        GL.glClear(GL.GL_DEPTH_BUFFER_BIT)
        return previous

    @staticmethod
    def end(previous: int) -> None:
        """Bind framebuffer ``previous`` again."""
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, previous)

    def delete(self) -> None:
        """Delete the texture and framebuffer (their context must be current)."""
        if self._fbo:
            GL.glDeleteFramebuffers(1, [self._fbo])
            GL.glDeleteTextures([self.texture])
        self._fbo, self.texture = 0, 0
