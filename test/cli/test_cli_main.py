"""The ``ebm-wear`` front door: a reader that goes away is not a crash."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

EBM = Path(sys.executable).parent / "ebm-wear"


def test_closed_stdout_ends_quietly_with_141():
    """`ebm-wear ... | head -0`: no BrokenPipeError traceback, the shell's 128 + SIGPIPE status."""
    proc = subprocess.Popen([EBM, "calc", "contact", "--params", "embu_000", "--axial-force", "20000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 141
    assert "Traceback" not in err and "BrokenPipe" not in err
