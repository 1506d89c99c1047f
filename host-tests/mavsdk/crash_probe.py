"""A test module that crashes its process as a client's native code does (a segmentation
fault), for `test_runner_contains_crashes.py`: never run by the suite itself (its name is
no `test_*.py`). `CRASH_PROBE=always` crashes every run; `CRASH_PROBE=once` crashes the
first run only (the file `CRASH_PROBE_MARK` remembers it)."""

import ctypes
import os
import unittest
from pathlib import Path


class CrashProbe(unittest.TestCase):
    def test_passes_then_the_process_crashes(self):
        self.assertTrue(True)
        mark = Path(os.environ["CRASH_PROBE_MARK"])
        if os.environ.get("CRASH_PROBE") == "always" or not mark.exists():
            mark.touch()
            # A read of address 0: SIGSEGV, as MAVSDK's library died on CI.
            ctypes.string_at(0)


if __name__ == "__main__":
    unittest.main()
