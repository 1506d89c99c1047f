"""Runs the real-client tests (every `test_*.py` here, or the modules named) and ends with
one line `N passed, N failed, N skipped` (docs/src/testing.md, "Real clients").

MAVSDK 4.1's Python package calls MAVSDK's C++ library inside the Python process (it
has no `mavsdk_server`): a crash of the client's native code kills the process that
runs the test. So each test module runs in a process of its own, the client's
(`run.py --module NAME...`), in a process group of its own, its output in a log of its
own. The runner reads the module's counts from its last line; a module whose process
dies by a signal (a segmentation fault, an abort) is reported as **the client's crash**,
with the signal and the tail of its log, and run once more; a second crash is a failure.
Whatever the module's process left running (the bridge and the simulated autopilot of
its rig) is ended with its process group.
"""

import faulthandler
import os
import re
import signal
import subprocess
import sys
import time
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
LOGS = Path(os.environ.get("MAVSDK_TESTS_LOGS", ROOT / "target" / "mavsdk-logs"))
COUNTS = re.compile(r"^(\d+) passed, (\d+) failed, (\d+) skipped$")
# Lines of a crashed module's log shown with its report.
TAIL = 60


def run_in_process(names):
    """The tests `names` (modules, or Module.Class.test) in this process: the counts."""
    sys.path.insert(0, str(HERE))
    loader = unittest.TestLoader()
    if names:
        suite = unittest.TestSuite(loader.loadTestsFromName(n) for n in names)
    else:
        suite = loader.discover(str(HERE), pattern="test_*.py", top_level_dir=str(HERE))
    result = unittest.TextTestRunner(verbosity=2, stream=sys.stdout).run(suite)
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    skipped = len(result.skipped)
    passed = result.testsRun - failed - skipped - len(result.expectedFailures)
    return passed, failed, skipped


def modules_of(names):
    """The modules to run, each with the names asked of it (empty: all of it)."""
    if not names:
        return {p.stem: [] for p in sorted(HERE.glob("test_*.py"))}
    out = {}
    for n in names:
        out.setdefault(n.split(".")[0], []).append(n)
    return out


def end_group(pgid):
    """Ends what is left of a module's process group (its rig's processes)."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(pgid, sig)
        except ProcessLookupError:
            return
        time.sleep(0.5)


def run_module(module, names, attempt):
    """One run of `module` in its own process: (counts or None, signal or None, log)."""
    LOGS.mkdir(parents=True, exist_ok=True)
    log = LOGS / f"{module}.{attempt}.log"
    with open(log, "w") as out:
        child = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), "--module", *(names or [module])],
            stdout=out,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
        )
        code = child.wait()
    end_group(child.pid)
    text = log.read_text(errors="replace")
    counts = None
    for line in reversed(text.splitlines()):
        m = COUNTS.match(line.strip())
        if m:
            counts = tuple(int(g) for g in m.groups())
            break
    died = -code if code < 0 else None
    return counts, died, log, text


def signal_name(number):
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def main(argv):
    if argv[:1] == ["--module"]:
        # A crash of the client's native code prints the Python stack of every thread
        # into the module's log.
        faulthandler.enable(all_threads=True)
        passed, failed, skipped = run_in_process(argv[1:])
        print(f"{passed} passed, {failed} failed, {skipped} skipped", flush=True)
        return 0 if failed == 0 else 1
    total = [0, 0, 0]
    crashes = []
    for module, names in modules_of(argv).items():
        for attempt in (1, 2):
            counts, died, log, text = run_module(module, names, attempt)
            sys.stdout.write(text)
            if died is None and counts is not None:
                break
            what = (f"died by {signal_name(died)}" if died is not None
                    else "ended without its counts")
            tail = "\n".join(text.splitlines()[-TAIL:])
            print(f"\nCLIENT CRASH: {module} {what} (MAVSDK's library runs in the module's "
                  f"process; attempt {attempt} of 2); log {log}, its last {TAIL} lines:\n"
                  f"{tail}\n", flush=True)
            crashes.append((module, attempt, what))
        if counts is None or died is not None:
            print(f"{module}: the client crashed twice: a failure", flush=True)
            total[1] += 1
            continue
        for i, n in enumerate(counts):
            total[i] += n
    if crashes:
        print("client crashes: " + "; ".join(f"{m} (attempt {a}: {w})" for m, a, w in crashes))
    print(f"{total[0]} passed, {total[1]} failed, {total[2]} skipped")
    return 0 if total[1] == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
