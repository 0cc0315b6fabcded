"""The Dask client of the fleet: an embedded local cluster sized to the machine, or an existing scheduler.

The embedded default starts one worker *process* per CPU core available to
this process, one thread each: the monitor core is numpy plus Python loops
per brake application, so threads would contend for the GIL while processes
scale. Everything (scheduler, workers, nannies, HTTP endpoint) listens on the
loopback interface only.

An existing scheduler is given in any form Dask itself accepts (:func:`scheduler_address`):
``host:port`` (tcp implied), ``tcp://host:port``, ``ws://host:port``, IPv6 in brackets, a host
alone (Dask's default port 8786). Refused with a one-line reason, before any work: ``tls://`` and
``wss://`` (they need TLS certificates, Dask security settings this tool does not take),
``inproc://`` (an in-process address, reachable only from inside the process that made it) and
``ucx://`` (a transport not installed here).
"""

from __future__ import annotations

import logging
import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from ebm_wear_monitor.errors import InputError

#: the scheduler's HTTP endpoint (health, and the dashboard where bokeh is installed): loopback,
#: a free port (the default 8787 collides with any other cluster on the machine)
LOOPBACK_ANY_PORT = "127.0.0.1:0"
#: how long to try reaching an existing scheduler before giving up [s]
CONNECT_TIMEOUT_S = 10.0
#: the port a Dask scheduler listens on by default (``dask scheduler``)
DASK_DEFAULT_PORT = 8786
_REFUSED = {
    "tls": "TLS needs certificates (Dask security settings), which ebm-wear fleet does not take; "
           "use tcp:// on a trusted network or through an SSH tunnel",
    "wss": "secure websockets need certificates (Dask security settings), which ebm-wear fleet does not "
           "take; use ws:// or tcp:// on a trusted network",
    "inproc": "an in-process address is reachable only from inside the process that made it; "
              "give the scheduler's tcp://host:port",
    "ucx": "the UCX transport is not installed here; use tcp://host:port",
}


def scheduler_address(text: str) -> str:
    """The canonical Dask address of a user-given scheduler address (see the module docstring).

    ``127.0.0.1:8799`` -> ``tcp://127.0.0.1:8799``; ``myhost`` -> ``tcp://myhost:8786``.
    InputError (one line) for an address this tool cannot use.
    """
    from distributed.comm.addressing import parse_address, parse_host_port, unparse_address

    try:
        scheme, location = parse_address(text.strip(), strict=False)
    except ValueError as exc:
        raise InputError(f"--scheduler {text}: not a Dask address ({exc})") from None
    if scheme in _REFUSED:
        raise InputError(f"--scheduler {text}: {_REFUSED[scheme]}")
    if scheme not in ("tcp", "ws"):
        raise InputError(f"--scheduler {text}: unknown protocol {scheme!r} (use tcp://host:port)")
    try:
        host, port = parse_host_port(location, default_port=DASK_DEFAULT_PORT)
    except ValueError as exc:
        raise InputError(f"--scheduler {text}: {exc}") from None
    if not host or not 0 < int(port) < 65536:
        raise InputError(f"--scheduler {text}: expected host:port with a port 1..65535")
    return unparse_address(scheme, f"[{host}]:{port}" if ":" in host else f"{host}:{port}")


def default_workers() -> int:
    """CPU cores this process may use (``sched_getaffinity``), at least 1."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


@contextmanager
def _sigint_ignored() -> Iterator[None]:
    """Worker processes started meanwhile ignore SIGINT (an ignored signal stays ignored across
    exec, and neither Python nor asyncio then installs a handler). Ctrl-C reaches the whole
    foreground process group; only this process should act on it (cancel, close the cluster,
    exit 130), not every worker with a KeyboardInterrupt traceback."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextmanager
def dask_client(scheduler: str | None = None, n_workers: int | None = None) -> Iterator:
    """A ``distributed.Client``: on ``scheduler`` (:func:`scheduler_address`) or on a new LocalCluster."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        address = scheduler_address(scheduler)
        try:
            client = Client(address, timeout=f"{CONNECT_TIMEOUT_S}s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"cannot connect to Dask scheduler {scheduler}: {exc}") from exc
        with client:
            yield client
        return
    # the embedded cluster's own log lines stay off the user's terminal (CRITICAL only): a task's error
    # reaches the client as its exception and becomes that unit's failure report, and a worker whose
    # scheduler went away at Ctrl-C would print heartbeat tracebacks after the one-line "interrupted"
    with _sigint_ignored():
        cluster = LocalCluster(n_workers=n_workers or default_workers(), threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=LOOPBACK_ANY_PORT,
                               silence_logs=logging.CRITICAL)
    with cluster, Client(cluster) as client:
        yield client
