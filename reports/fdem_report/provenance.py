"""Where and how the numbers were made: build (commit, build type, compiler),
machine (hostname, cores, CPU model), date, and each study's wall time, so that
two reports can be compared line by line."""
from __future__ import annotations

import datetime
import os
import platform
import socket
import subprocess
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


def fnv1a64(path: Path) -> str:
    """64-bit FNV-1a of a file's bytes, as verification/support/study_io.cpp
    writes it into meta.json ("" if unreadable)."""
    try:
        data = path.read_bytes()
    except OSError:
        return ""
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def source_commit(root: Path) -> str | None:
    """HEAD of the source tree the report belongs to (None outside git)."""
    try:
        out = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True,
                             timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    head = out.stdout.strip()
    return head if out.returncode == 0 and len(head) == 40 else None


def staleness(meta: dict | None, expected_commit: str | None, root: Path) -> str:
    """Why a study's results are not those of `expected_commit` and of the
    scene now in the tree ("" when they are, or when nothing can be checked)."""
    if meta is None or expected_commit is None:
        return ""
    commit = meta.get("commit")
    if not commit:
        return "STALE: meta.json names no commit (written before run provenance); rerun the study"
    if commit != "unknown" and not (commit.startswith(expected_commit) or expected_commit.startswith(commit)):
        return f"STALE: results of commit {commit[:10]}, report for {expected_commit[:10]}"
    scene = meta.get("scene")
    if isinstance(scene, dict) and scene.get("file") and scene.get("fnv1a64"):
        now = fnv1a64(root / str(scene["file"]))
        if now and now != scene["fnv1a64"]:
            return f"STALE: {scene['file']} changed since the run (hash {scene['fnv1a64']} then, {now} now)"
    return ""


def run_summary(meta: dict | None) -> str:
    """One line of a run's provenance for the study table."""
    if not meta:
        return ""
    parts = []
    if meta.get("commit"):
        parts.append(f"commit {str(meta['commit'])[:10]}" + (" (dirty tree)" if meta.get("dirty") else ""))
    if meta.get("finished_utc"):
        parts.append(f"finished {meta['finished_utc']}")
    if meta.get("threads") is not None:
        parts.append(f"{meta['threads']} thread(s)")
    scene = meta.get("scene")
    if isinstance(scene, dict) and scene.get("file"):
        parts.append(f"scene {scene['file']} ({scene.get('fnv1a64', '')})")
    params = meta.get("parameters")
    if isinstance(params, dict) and params:
        parts.append("; ".join(f"{k} = {v}" for k, v in params.items()))
    return ", ".join(parts)
