"""MAVSDK's camera and gimbal plugins, as a ground app uses them, against the bridge
behind the simulated PX4 (mode Normal, its GCS link on UDP, gimbal manager of the
bridge's gimbal): discovery, information, a photo with its capture information, video,
zoom, focus, storage, gimbal angles through the manager (docs/src/testing.md;
what MAVSDK does, as observed: docs/src/autopilots/qgroundcontrol.md)."""

import math
import threading
import time
import unittest

from mavsdk.plugins.camera import Camera, CameraError
from mavsdk.plugins.gimbal import Gimbal, GimbalMode, SendMode

from rig import CAMERA, GIMBAL_COMPONENT, Rig, attempt, wait_for

RIG = None


def setUpModule():
    global RIG
    # The bridge's UTC on small bins (valid within a few seconds).
    RIG = Rig("px4", bridge_args=["--discipline-bin-ms", "1000", "--discipline-min-bins", "3",
                                  "--discipline-min-span-ms", "2000"]).start()


def tearDownModule():
    if RIG is not None:
        RIG.stop()


def camera_listed(camera):
    cams = camera.camera_list().cameras
    return [c for c in cams if c.component_id == CAMERA]


class Px4CameraTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.camera = Camera(RIG.system)
        wait_for("camera 100 in MAVSDK's camera list", lambda: camera_listed(cls.camera), 15)

    def test_1_discovery_and_information(self):
        """The camera is listed with the vendor and model of CAMERA_INFORMATION; the
        bridge's gimbal (154) and camera (100) heartbeats reach MAVSDK through PX4."""
        (info,) = camera_listed(self.camera)
        self.assertEqual(info.vendor_name, "K40T")
        self.assertEqual(info.model_name, "K40T four-sensor pod")
        # The focal length the pod reports (0x000005: 4.50 mm at 1x), as MAVSDK copies
        # it; the bridge's lens configuration has none.
        self.assertAlmostEqual(info.focal_length_mm, 4.5, places=3)
        self.assertTrue({1, CAMERA, GIMBAL_COMPONENT} <= RIG.components(), RIG.components())
        # Only the camera is a camera: the gimbal NACKs camera requests.
        self.assertEqual(len(self.camera.camera_list().cameras), 1)

    def test_2_photo_with_capture_information(self):
        """One take_photo: ACCEPTED after the pod's ACK, exactly one capture
        information, successful, with the photo's UTC and position."""
        # As in flight: the pod's clock synced before the photo (its time names the photo).
        wait_for("the pod's first time sync",
                 lambda: [e for e in RIG.bridge.events("sim_pod_sync") if e["outcome"] == "applied"],
                 25)
        captures = []
        lock = threading.Lock()

        def on_capture(info, _):
            with lock:
                captures.append(info)

        handle = self.camera.subscribe_capture_info(on_capture)
        try:
            before = len(RIG.pod_photos())
            t0 = time.time()
            self.camera.take_photo(CAMERA)
            wait_for("the capture information", lambda: captures, 10)
            time.sleep(2.0)  # anything more would come within this
        finally:
            self.camera.unsubscribe_capture_info(handle)
        self.assertEqual(len(captures), 1, [str(c) for c in captures])
        c = captures[0]
        self.assertTrue(c.is_success, str(c))
        self.assertEqual(c.component_id, CAMERA)
        # The photo's UTC: within the second of the shutter (the host's clock is UTC).
        self.assertLess(abs(c.time_utc_us / 1e6 - t0), 2.0, str(c))
        # The simulated aircraft flies from 47.3977 N, 8.5456 E.
        self.assertAlmostEqual(c.position.latitude_deg, 47.3977, delta=0.01)
        self.assertAlmostEqual(c.position.longitude_deg, 8.5456, delta=0.01)
        self.assertGreater(c.position.absolute_altitude_m, 400)
        self.assertEqual(len(RIG.pod_photos()) - before, 1)

    def test_3_video_start_stop(self):
        self.camera.start_video(CAMERA)
        wait_for("video on in the capture status",
                 lambda: getattr(attempt(lambda: self.camera.get_storage(CAMERA)), 'video_on', False), 10)
        self.camera.stop_video(CAMERA)
        wait_for("video off in the capture status",
                 lambda: getattr(attempt(lambda: self.camera.get_storage(CAMERA)), 'video_on', True) is False, 10)

    def test_4_zoom_and_focus(self):
        """Zoom range and continuous, focus steps and auto: each ACCEPTED after the
        pod's ACK."""
        self.camera.zoom_range(CAMERA, 50.0)
        self.camera.zoom_in_start(CAMERA)
        self.camera.zoom_stop(CAMERA)
        self.camera.zoom_out_start(CAMERA)
        self.camera.zoom_stop(CAMERA)
        self.camera.focus_in_start(CAMERA)
        self.camera.focus_stop(CAMERA)
        self.camera.focus_auto(CAMERA)
        with self.assertRaises(CameraError):
            # Focus by distance is not the pod's: UNSUPPORTED.
            self.camera.focus_meters(CAMERA, 10.0)

    def test_5_storage(self):
        s = wait_for("a storage report", lambda: attempt(lambda: self.camera.get_storage(CAMERA)), 10)
        self.assertEqual(s.storage_status, s.StorageStatus.FORMATTED, str(s))
        self.assertGreater(s.total_storage_mib, 0)
        self.assertEqual(s.storage_id, 1)


class Px4GimbalTest(unittest.TestCase):
    def test_angles_through_the_manager(self):
        """PX4 is the gimbal manager (GIMBAL_MANAGER_INFORMATION with device 154): the
        gimbal is listed, set_angles (DO_GIMBAL_MANAGER_PITCHYAW to PX4, which streams
        GIMBAL_DEVICE_SET_ATTITUDE to 154) turns the pod, and the attitude MAVSDK reads
        back (the device's own GIMBAL_DEVICE_ATTITUDE_STATUS) follows."""
        gimbal = Gimbal(RIG.system)
        gimbals = wait_for("a gimbal in MAVSDK's list", lambda: gimbal.gimbal_list().gimbals, 15)
        self.assertEqual(len(gimbals), 1)
        g = gimbals[0]
        self.assertEqual(g.gimbal_manager_component_id, 1)
        self.assertEqual(g.gimbal_device_id, GIMBAL_COMPONENT)
        gimbal.set_angles(g.gimbal_id, 0.0, -30.0, 20.0, GimbalMode.YAW_FOLLOW, SendMode.ONCE)

        def there():
            att = attempt(lambda: gimbal.get_attitude(g.gimbal_id))
            if att is None:
                return None
            a = att.euler_angle_forward
            return abs(a.pitch_deg + 30.0) < 1.5 and abs(a.yaw_deg - 20.0) < 1.5 and a

        wait_for("the pod at pitch -30, yaw 20", there, 15)


if __name__ == "__main__":
    unittest.main()
