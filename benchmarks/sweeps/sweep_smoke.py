"""What the sweep drivers' smoke tests (check_sweep.py, check_plume_sweep.py)
share: run the driver in its smallest mode into the output folder, print what
it said, and read the file it wrote with the report's own strict reader
(reports/fdem_report: the consumer's contract)."""
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "reports"))


class SmokeFailure(Exception):
    """The check's one-line reason; main() prints it as `<check>: FAIL: <reason>`."""


def run_and_read(mode: str, csv_name: str, schema_name: str):
    """Run argv[1] (the driver) with `mode` into argv[2]; (output folder, its table)."""
    exe, out = sys.argv[1], Path(sys.argv[2])
    r = subprocess.run([exe, mode, "--out", str(out)], text=True, capture_output=True, timeout=280)
    print(r.stdout)
    if r.returncode != 0:
        raise SmokeFailure(f"{Path(exe).name} exited {r.returncode}: {r.stderr}")
    from fdem_report import csvio, formats  # the consumer's contract
    return out, csvio.read_table(out / csv_name, getattr(formats, schema_name))


def report(check: str, run) -> int:
    """Exit code of run() (0 when it returns), a raised SmokeFailure printed and 1."""
    try:
        run()
    except SmokeFailure as e:
        print(f"{check}: FAIL: {e}", file=sys.stderr)
        return 1
    return 0
