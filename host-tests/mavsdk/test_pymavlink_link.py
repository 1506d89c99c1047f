"""pymavlink as the ground app, for what MAVSDK has no API for (the other tests of this
kind build on it): through the simulated PX4 the bridge's components heartbeat, a
REQUEST_MESSAGE(CAMERA_INFORMATION) to 1/100 is ACKed then answered from 100, and the
gimbal's attitude status reaches the ground (docs/src/testing.md)."""

import unittest

from rig import CAMERA, GIMBAL_COMPONENT, Rig

RIG = None


def setUpModule():
    global RIG
    RIG = Rig("px4").start(client="pymavlink")


def tearDownModule():
    if RIG is not None:
        RIG.stop()


class PymavlinkLinkTest(unittest.TestCase):
    def test_heartbeats_request_message_and_attitude_status(self):
        seen = set()
        RIG.recv("HEARTBEAT", lambda m: seen.add(m.get_srcComponent()) or
                 {1, CAMERA, GIMBAL_COMPONENT} <= seen, 10)
        mav = RIG.mav.mav
        # MAV_CMD_REQUEST_MESSAGE (512) for CAMERA_INFORMATION (259).
        mav.command_long_send(1, CAMERA, 512, 0, 259, 0, 0, 0, 0, 0, 0)
        ack = RIG.recv("COMMAND_ACK", lambda m: m.command == 512, 10)
        self.assertEqual(ack.get_srcComponent(), CAMERA)
        self.assertEqual(ack.result, 0)
        info = RIG.recv("CAMERA_INFORMATION", lambda m: m.get_srcComponent() == CAMERA, 10)
        self.assertEqual(info.vendor_name.rstrip("\x00") if isinstance(info.vendor_name, str)
                         else bytes(info.vendor_name).rstrip(b"\x00").decode(), "K40T")
        status = RIG.recv("GIMBAL_DEVICE_ATTITUDE_STATUS",
                          lambda m: m.get_srcComponent() == GIMBAL_COMPONENT, 10)
        self.assertEqual(status.target_system, 0)


if __name__ == "__main__":
    unittest.main()
