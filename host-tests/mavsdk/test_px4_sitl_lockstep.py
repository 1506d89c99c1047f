"""MAVSDK through a simulated PX4 SITL in lockstep (its boot clock in 4 ms steps, 0.87 %
slow against its UTC, the host's, as the recorded PX4 v1.16 SITL): the bridge's UTC holds (no `utc_lost` once valid) and a photo's
capture information carries the photo's UTC and position (docs/src/autopilots/px4.md,
"SITL in lockstep")."""

import threading
import time
import unittest

from mavsdk.plugins.camera import Camera

from rig import CAMERA, Rig, wait_for

RIG = None


def setUpModule():
    global RIG
    RIG = Rig("px4", sim_args=["--px4-lockstep"]).start()


def tearDownModule():
    if RIG is not None:
        RIG.stop()


class Px4SitlLockstepTest(unittest.TestCase):
    def test_utc_holds_and_a_photo_is_geotagged(self):
        camera = Camera(RIG.system)
        wait_for("camera 100 listed",
                 lambda: [c for c in camera.camera_list().cameras if c.component_id == CAMERA],
                 15)
        wait_for("the pod's first time sync",
                 lambda: [e for e in RIG.bridge.events("sim_pod_sync")
                          if e["outcome"] == "applied"],
                 25)
        captures = []
        lock = threading.Lock()

        def on_capture(info, _):
            with lock:
                captures.append(info)

        handle = camera.subscribe_capture_info(on_capture)
        try:
            t0 = time.time()
            camera.take_photo(CAMERA)
            wait_for("the capture information", lambda: captures, 10)
            time.sleep(1.0)
        finally:
            camera.unsubscribe_capture_info(handle)
        self.assertEqual(len(captures), 1, [str(c) for c in captures])
        c = captures[0]
        self.assertTrue(c.is_success, str(c))
        self.assertLess(abs(c.time_utc_us / 1e6 - t0), 2.0, str(c))
        self.assertAlmostEqual(c.position.latitude_deg, 47.3977, delta=0.01)
        valid = RIG.bridge.events("utc_valid")
        self.assertTrue(valid, RIG.report("UTC never valid"))
        first = valid[0]["t_us"]
        lost = [e for e in RIG.bridge.events("utc_lost") if e["t_us"] > first]
        self.assertEqual(lost, [], RIG.report("UTC lost after it became valid"))
        applied = [e for e in RIG.bridge.events("sim_pod_sync") if e["outcome"] == "applied"]
        self.assertTrue(applied)


if __name__ == "__main__":
    unittest.main()
