"""What the side-by-side benchmarks share: how busy the machine is, waiting
until it is quiet before a timed run, and installing a peer code from
Debian's packages when it is missing (benchmarks/dem/side_by_side.py,
benchmarks/fluid/settling_vs_dpmfoam.py)."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time


def busy_cores() -> float:
    """CPU seconds every process has used since boot (user + nice + system + irq ...)."""
    fields = [int(x) for x in open("/proc/stat").readline().split()[1:]]
    return (sum(fields[:8]) - fields[3] - fields[4]) / os.sysconf("SC_CLK_TCK")


def wait_quiet(limit_s: float) -> float:
    """Samples the load over 2 s until under 0.1 core or limit_s has passed; returns the last sample."""
    deadline = time.time() + limit_s
    while True:
        b0 = busy_cores()
        time.sleep(2)
        load = (busy_cores() - b0) / 2
        if load < 0.1 or time.time() >= deadline:
            return load
        print(f"  waiting for a quiet machine: {load:.2f} cores busy", flush=True)


def ensure_installed(commands: list[str], package: str, who: str) -> None:
    """apt-get installs package unless every command is on PATH; refuses without root."""
    if all(shutil.which(c) for c in commands):
        return
    if os.geteuid() != 0:
        sys.exit(f"{who}: {commands[0]} not installed (apt-get install {package})")
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(["apt-get", "update"], check=True, env=env)
    subprocess.run(["apt-get", "install", "-y", package], check=True, env=env)
