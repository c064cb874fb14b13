"""One way for the session tests to run scripts/linuxcnc-sim: exit 3 means another session holds
the realtime (a LinuxCNC or a halrun of another build on this machine), so it is waited out, up to
two minutes, rather than failed."""

import subprocess
import time


def run_linuxcnc_sim(cmd, env=None):
    """subprocess.run(cmd) (captured text), again while it exits 3, at most 120 times a second
    apart; the last CompletedProcess."""
    for _ in range(120):
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=240, env=env)
        if p.returncode != 3:
            break
        time.sleep(1.0)
    return p
