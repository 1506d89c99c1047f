"""MAVSDK's storage format against the bridge configured to allow it
(`--mavlink-allow-destructive`) behind the simulated ArduPilot: ACCEPTED after the
simulated pod's ACK, and the card then reported empty (docs/src/bridge/mavlink.md,
"Storage and reset"; docs/src/testing.md); while recording the pod refuses it."""

import unittest

from mavsdk.plugins.camera import Camera, CameraError

from rig import CAMERA, Rig, attempt, wait_for

RIG = None


def setUpModule():
    global RIG
    RIG = Rig("ardupilot", bridge_args=["--mavlink-allow-destructive"]).start()


def tearDownModule():
    if RIG is not None:
        RIG.stop()


class CameraStorageTest(unittest.TestCase):
    def test_format_empties_the_card(self):
        camera = Camera(RIG.system)
        wait_for("camera 100 listed",
                 lambda: [c for c in camera.camera_list().cameras if c.component_id == CAMERA], 15)
        before = wait_for("a storage report with a used card",
                          lambda: attempt(lambda: camera.get_storage(CAMERA)), 15)
        self.assertGreater(before.used_storage_mib, 0, str(before))
        # Not while recording (K40T external protocol, 3.2.4.12): FAILED.
        camera.start_video(CAMERA)
        with self.assertRaises(CameraError):
            camera.format_storage(CAMERA, 1)
        camera.stop_video(CAMERA)
        camera.format_storage(CAMERA, 1)

        def empty():
            s = attempt(lambda: camera.get_storage(CAMERA))
            return s is not None and s.used_storage_mib == 0 and s

        after = wait_for("the card reported empty", empty, 15)
        self.assertEqual(after.storage_status, after.StorageStatus.FORMATTED, str(after))
        self.assertEqual(after.available_storage_mib, after.total_storage_mib)
        self.assertEqual(RIG.bridge.events("destructive_denied"), [])


if __name__ == "__main__":
    unittest.main()
