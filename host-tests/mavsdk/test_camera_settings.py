"""MAVSDK's camera settings against the bridge behind the simulated PX4: the camera
definition downloaded over MAVLink FTP (OpenFileRO, ReadFile..., TerminateSession) and
inflated, the settings listed with their options, set and read back (PARAM_EXT_*, each
set answered after the simulated pod's ACK), a set the pod refuses, and storage format
refused without `mavlink.allow_destructive` (docs/src/bridge/mavlink.md, "Settings and
the camera definition"; docs/src/testing.md)."""

import unittest
from pathlib import Path

from mavsdk.plugins.camera import Camera, CameraError, Option, Setting

from rig import CAMERA, ROOT, Rig, attempt, wait_for

RIG = None
XML = (ROOT / "bridge-engine" / "camera" / "k40t.xml").read_text()
# MAVSDK keeps a definition it has downloaded, by model, vendor and version.
CACHE = Path.home() / ".cache" / "mavsdk" / "camera"


def setUpModule():
    global RIG
    # Its own download, not a copy cached by an earlier run.
    for f in CACHE.glob("camera_definition-K40T*"):
        f.unlink()
    RIG = Rig("px4").start()


def tearDownModule():
    if RIG is not None:
        RIG.stop()


def setting(setting_id, option_id=""):
    return Setting(setting_id, "", Option(option_id, ""), False)


class CameraSettingsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.camera = Camera(RIG.system)
        cls.options = wait_for(
            "the definition's settings",
            lambda: attempt(lambda: cls.camera.get_possible_setting_options(CAMERA)),
            20)

    def get(self, setting_id):
        return self.camera.get_setting(CAMERA, setting(setting_id)).option.option_id

    def test_1_the_definition_downloaded_byte_for_byte(self):
        """MAVSDK lists the definition's parameters but CAM_MODE (its own mode switch)
        and those the current values exclude (burst count and time-lapse interval in
        single-shot mode, the levels of switches that are off), with the options of the
        XML; the file it keeps is the XML."""
        ids = {o.setting_id for o in self.options}
        excluded = {"CAM_BURST", "CAM_LAPSE", "CAM_HLSUPP_LV", "CAM_BACKLIGHT_LV"}
        self.assertEqual(len(ids), 32 - len(excluded), sorted(ids))
        self.assertFalse(ids & excluded)
        self.assertTrue({"CAM_ISO", "CAM_EV", "IR_PALETTE", "IR_SHARPNESS"} <= ids)
        iso = next(o for o in self.options if o.setting_id == "CAM_ISO")
        self.assertEqual([o.option_id for o in iso.options], [str(v) for v in range(8)])
        self.assertEqual(iso.options[3].option_description, "400")
        sharpness = next(o for o in self.options if o.setting_id == "IR_SHARPNESS")
        self.assertTrue(sharpness.is_range)
        cached = wait_for("the cached definition", lambda: list(CACHE.glob("camera_definition-K40T*")), 5)
        self.assertEqual(cached[0].read_text(), XML)

    def test_2_settings_set_and_read_back(self):
        """The current values are the pod's (its defaults); each set ACCEPTED after the
        pod's ACK, and read back."""
        def current_values():
            # MAVSDK fills its current settings as the values arrive: wait for all.
            values = {s.setting_id: s.option.option_id
                      for s in attempt(lambda: self.camera.get_current_settings(CAMERA)) or []}
            return values if len(values) >= len(self.options) else None
        current = wait_for("the current values", current_values, 10)
        self.assertEqual(current.get("CAM_ISO"), "0", current)
        self.assertEqual(current.get("IR_PALETTE"), "1", current)
        for setting_id, option_id in [("CAM_ISO", "3"), ("IR_PALETTE", "5"),
                                      ("CAM_EV", "16"), ("IR_SHARPNESS", "80"),
                                      ("CAM_VIDRES", "38")]:
            self.camera.set_setting(CAMERA, setting(setting_id, option_id))
            wait_for(f"{setting_id} {option_id} read back",
                     lambda: self.get(setting_id) == option_id, 10)

    def test_3_exclusions_hold(self):
        """Strong-light suppression on: the level appears, backlight compensation is
        excluded (the pod would refuse it, K40T external protocol 3.2.3.10) and MAVSDK
        refuses to set it; its value stays off. (The pod's own refusals, through the
        same PARAM_EXT_ACK FAILED: bridge_mavlink_settings.rs.)"""
        self.camera.set_setting(CAMERA, setting("CAM_HLSUPP", "1"))
        ids = wait_for(
            "the level among the settings",
            lambda: (lambda o: o and {x.setting_id for x in o} if o and "CAM_HLSUPP_LV" in
                     {x.setting_id for x in o} else None)(
                attempt(lambda: self.camera.get_possible_setting_options(CAMERA))),
            10)
        self.assertNotIn("CAM_BACKLIGHT", ids)
        with self.assertRaises(CameraError):
            self.camera.set_setting(CAMERA, setting("CAM_BACKLIGHT", "1"))
        self.assertEqual(self.get("CAM_BACKLIGHT"), "0")

    def test_4_storage_format_is_refused_by_default(self):
        """Without `mavlink.allow_destructive` the format is DENIED, and the bridge says
        why."""
        with self.assertRaises(CameraError):
            self.camera.format_storage(CAMERA, 1)
        denied = wait_for("the destructive_denied event",
                          lambda: RIG.bridge.events("destructive_denied"), 5)
        self.assertEqual(denied[0]["command"], 526)


if __name__ == "__main__":
    unittest.main()
