"""The Dask client of the fleet: an embedded local cluster sized to the machine, or an existing scheduler.

The embedded default starts one worker *process* per CPU core available to
this process, one thread each: the monitor core is numpy plus Python loops
per brake application, so threads would contend for the GIL while processes
scale. Everything (scheduler, workers, nannies, HTTP endpoint) listens on the
loopback interface only.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from contextlib import contextmanager

from ebm_wear_monitor.errors import InputError

#: the scheduler's HTTP endpoint (health, and the dashboard where bokeh is installed): loopback,
#: a free port (the default 8787 collides with any other cluster on the machine)
LOOPBACK_ANY_PORT = "127.0.0.1:0"
#: how long to try reaching an existing scheduler before giving up [s]
CONNECT_TIMEOUT_S = 10.0


def default_workers() -> int:
    """CPU cores this process may use (``sched_getaffinity``), at least 1."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


@contextmanager
def dask_client(scheduler: str | None = None, n_workers: int | None = None) -> Iterator:
    """A ``distributed.Client``: on ``scheduler`` (``tcp://host:port``) or on a new LocalCluster."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"cannot connect to Dask scheduler {scheduler}: {exc}") from exc
        with client:
            yield client
        return
    cluster = LocalCluster(n_workers=n_workers or default_workers(), threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address=LOOPBACK_ANY_PORT, silence_logs=logging.ERROR)
    with cluster, Client(cluster) as client:
        yield client
