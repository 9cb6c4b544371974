"""Where and how the numbers were made: build (commit, build type, compiler),
machine (hostname, cores, CPU model), date, and each study's wall time, so that
two reports can be compared line by line."""
from __future__ import annotations

import datetime
import os
import platform
import socket
from pathlib import Path

from .csvio import read_json


def cpu_model(cpuinfo: Path = Path("/proc/cpuinfo")) -> str:
    try:
        for line in cpuinfo.read_text(errors="replace").splitlines():
            if line.lower().startswith(("model name", "hardware", "cpu model")):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def collect(build_info: Path | None) -> list[tuple[str, str]]:
    """(label, value) pairs, in the order shown."""
    info = {}
    if build_info is not None and build_info.is_file():
        info = read_json(build_info)
    missing = "unknown (no build_info.json)" if not info else "unknown"
    items = [
        ("commit", str(info.get("commit", missing))),
        ("version", str(info.get("version", missing))),
        ("build type", str(info.get("build_type", missing))),
        ("compiler", str(info.get("compiler", missing))),
        ("sanitizers", str(info.get("sanitize", missing))),
        ("machine", socket.gethostname()),
        ("cores (nproc)", str(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count())),
        ("CPU", cpu_model()),
        ("OS", f"{platform.system()} {platform.release()}"),
        ("report date (UTC)", datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S")),
        ("build info", str(build_info) if build_info is not None else "not given"),
    ]
    return items
