"""Start a viser server safely: on 127.0.0.1 unless another host is asked for (then one
warning line, since anyone who can reach the port can drive the arm), on exactly the
port asked for (viser's own default binds 0.0.0.0 and moves on to the next port when one
is busy; neither happens here), never fetching anything from the network (no share
button, no logo link), and with viser's console chatter off.

The only files the server hands out are the ones of viser's bundled client (its
``client/build`` folder, paths with ``..`` refused); no path from the browser reaches
anything of ours.
"""
from __future__ import annotations

import contextlib
import io
import ipaddress
import socket
import sys
from typing import Any, TextIO

#: Hosts that only this machine can reach.
LOOPBACK_HOSTS = ("127.0.0.1", "localhost", "::1")
DEFAULT_HOST = "127.0.0.1"
#: The port ``robot-sim --web`` serves on unless --port says otherwise.
DEFAULT_PORT = 8080
PORT_RANGE = (1, 65535)


class WebServerError(ValueError):
    """The server cannot start as asked (bad host or port, port in use); the message is one
    line naming the option, the value and what is accepted."""


def is_loopback(host: str) -> bool:
    """True when ``host`` can be reached from this machine only."""
    if host in LOOPBACK_HOSTS:
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def exposure_warning(host: str, port: int) -> str | None:
    """The one warning line for a server reachable from other machines, or None."""
    if is_loopback(host):
        return None
    return (f"warning: serving on {host}:{port}: anyone who can reach this port can see "
            "and drive the arm (use --host 127.0.0.1 and an SSH tunnel instead)")


def check_port(host: str, port: int | None) -> None:
    """WebServerError unless ``port`` (None or 0: any free one) is a valid port number that
    is free on ``host``.  Checked by binding it once, because viser would silently take the
    next free port instead."""
    if port is None or port == 0:
        return
    if isinstance(port, bool) or not isinstance(port, int) or not PORT_RANGE[0] <= port <= PORT_RANGE[1]:
        raise WebServerError(f"port: expected a whole number {PORT_RANGE[0]}..{PORT_RANGE[1]}, got {str(port)[:80]!r}")
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except (OSError, UnicodeError) as exc:
        raise WebServerError(f"host: cannot resolve {host[:80]!r} ({exc.__class__.__name__})") from None
    family, _, _, _, address = infos[0]
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind(address)
        except OSError:
            raise WebServerError(f"port: {port} on {host[:80]} is in use; choose another with --port") from None


def start_server(host: str = DEFAULT_HOST, port: int | None = None, *, label: str = "robot-sim",
                 dark: bool = True, warn: TextIO | None = sys.stderr) -> Any:
    """A running ``viser.ViserServer`` on ``host``:``port`` (None: a free port chosen by the
    system), or WebServerError.  A host other than a loopback one writes
    :func:`exposure_warning` to ``warn``."""
    if not isinstance(host, str) or not host:
        raise WebServerError(f"host: expected a host name or address, got {str(host)[:80]!r}")
    check_port(host, port)
    import viser  # the web server is loaded only when a browser view is asked for
    from viser import _messages

    with contextlib.redirect_stdout(io.StringIO()):  # viser prints a banner whatever verbose says
        server = viser.ViserServer(host=host, port=port or 0, label=label, verbose=False)
    # the page's share button asks viser to open a tunnel to its share service: a
    # connection from this machine to the internet that a browser could trigger
    server._websock_server.unregister_handler(_messages.ShareUrlRequest)
    bound = server.get_port()
    if port and bound != port:  # someone took the port between the check and the bind
        stop_server(server)
        raise WebServerError(f"port: {port} on {host[:80]} is in use; choose another with --port")
    server.gui.configure_theme(dark_mode=dark, show_logo=False, show_share_button=False, control_width="medium")
    line = exposure_warning(host, bound)
    if line is not None and warn is not None:
        print(line, file=warn)
    return server


def server_url(server: Any) -> str:
    """The address a browser on this machine opens for ``server``."""
    host = server.get_host()
    shown = "127.0.0.1" if host in ("0.0.0.0", "localhost") else host
    if ":" in shown:
        shown = f"[{shown}]"
    return f"http://{shown}:{server.get_port()}/"


def stop_server(server: Any) -> None:
    """Stop ``server`` and wait for its thread, without viser's console line."""
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()
