"""``lcpfric map --scheduler``: the Dask scheduler's address, checked (and reached) before any
work, and the client (standard library at module level)."""

from __future__ import annotations

import re

from . import _common
from ..errors import InputError

__all__ = ["scheduler_address", "connect", "PROBE_SECONDS", "CONNECT_SECONDS"]

_ADDRESS = re.compile(
    r"^(?:(?P<scheme>[A-Za-z][A-Za-z0-9+.-]*)://)?"
    r"(?P<host>\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):(?P<port>\d{1,5})$"
)
_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")
PROBE_SECONDS = 5.0


def scheduler_address(text) -> str:
    """Check a Dask scheduler address, and that something listens there, before any work."""
    import socket

    s = str(text).strip()
    m = _ADDRESS.match(s)
    scheme = (m.group("scheme") or "tcp").lower() if m else ""
    if m is None or scheme not in _SCHEMES or not 0 < int(m.group("port")) < 65536:
        raise InputError(
            "--scheduler",
            f"{text!r} is not a Dask scheduler address; give "
            "tcp://HOST:PORT or HOST:PORT, e.g. tcp://10.0.0.5:8786",
        )
    host, port = m.group("host").strip("[]"), int(m.group("port"))
    address = s if m.group("scheme") else f"tcp://{s}"
    if scheme != "ucx":
        try:
            socket.create_connection((host, port), timeout=PROBE_SECONDS).close()
        except socket.gaierror:
            raise InputError(
                "--scheduler",
                f"cannot reach the Dask scheduler at {address}: unknown host {host!r}",
            ) from None
        except (OSError, TimeoutError) as exc:
            reason = getattr(exc, "strerror", None) or type(exc).__name__
            if isinstance(exc, TimeoutError):
                reason = f"no answer within {PROBE_SECONDS:g} s"
            raise InputError(
                "--scheduler", f"cannot reach the Dask scheduler at {address}: {reason}"
            ) from None
    return address


CONNECT_SECONDS = 20


def connect(address: str):
    """A ``dask.distributed.Client`` of the scheduler at ``address``; any failure to connect is
    bad input for ``--scheduler`` (a service there that is not a Dask scheduler makes Dask's
    reader fail in odd ways, a MemoryError among them)."""
    from distributed import Client

    try:
        return Client(address, timeout=f"{CONNECT_SECONDS}s")
    except MemoryError:
        reason = "what answers there does not speak Dask's protocol"
    except Exception as exc:  # OSError, TimeoutError, a protocol error...
        reason = f"{type(exc).__name__}: {exc}"
    raise InputError(
        "--scheduler",
        f"cannot connect to a Dask scheduler at {address}: {_common.one_line(reason)}",
    )
