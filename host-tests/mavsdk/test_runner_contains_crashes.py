"""The runner contains a client's crash (run.py): a module whose process dies by a signal
is reported as the client's crash with its log and run once more; a second crash is a
failure. Runs run.py on `crash_probe.py` (no MAVSDK, no rig: about a second)."""

import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent


def run(mode, logs):
    mark = Path(logs) / "mark"
    env = dict(os.environ, CRASH_PROBE=mode, CRASH_PROBE_MARK=str(mark),
               MAVSDK_TESTS_LOGS=str(logs))
    p = subprocess.run([sys.executable, str(HERE / "run.py"), "crash_probe"], env=env,
                       capture_output=True, text=True, timeout=60, check=False)
    return p.returncode, p.stdout


class RunnerContainsCrashes(unittest.TestCase):
    def test_one_crash_is_reported_with_its_log_and_the_module_run_again(self):
        with tempfile.TemporaryDirectory() as logs:
            code, out = run("once", logs)
            self.assertEqual(code, 0, out)
            self.assertIn("CLIENT CRASH: crash_probe died by SIGSEGV", out)
            self.assertIn("attempt 1 of 2", out)
            # The crashed run's log is kept and its tail shown.
            self.assertTrue((Path(logs) / "crash_probe.1.log").exists())
            self.assertIn("test_passes_then_the_process_crashes", out)
            self.assertEqual(out.strip().splitlines()[-1], "1 passed, 0 failed, 0 skipped")

    def test_a_second_crash_is_a_failure(self):
        with tempfile.TemporaryDirectory() as logs:
            code, out = run("always", logs)
            self.assertEqual(code, 1, out)
            self.assertIn("attempt 2 of 2", out)
            self.assertIn("crash_probe: the client crashed twice: a failure", out)
            self.assertEqual(out.strip().splitlines()[-1], "0 passed, 1 failed, 0 skipped")


if __name__ == "__main__":
    unittest.main()
