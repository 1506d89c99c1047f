"""MAVSDK's camera plugin through the simulated ArduPilot (Copter, `MNT1_TYPE` 6 and
`CAM1_TYPE` 6, its GCS link on UDP, routing as ArduPilot routes): the camera listed and
a photo's capture information (docs/src/testing.md)."""

import threading
import unittest

from mavsdk.plugins.camera import Camera

from rig import CAMERA, GIMBAL_COMPONENT, Rig, wait_for

RIG = None


def setUpModule():
    global RIG
    RIG = Rig("ardupilot").start()


def tearDownModule():
    if RIG is not None:
        RIG.stop()


class ArduPilotCameraTest(unittest.TestCase):
    def test_camera_listed_and_one_photo_one_capture(self):
        camera = Camera(RIG.system)
        cams = wait_for(
            "camera 100 listed",
            lambda: [c for c in camera.camera_list().cameras if c.component_id == CAMERA],
            15)
        self.assertEqual(cams[0].vendor_name, "K40T")
        self.assertTrue({1, CAMERA, GIMBAL_COMPONENT} <= RIG.components())
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
            camera.take_photo(CAMERA)
            wait_for("the capture information", lambda: captures, 10)
        finally:
            camera.unsubscribe_capture_info(handle)
        self.assertEqual(len(captures), 1)
        self.assertTrue(captures[0].is_success, str(captures[0]))


if __name__ == "__main__":
    unittest.main()
