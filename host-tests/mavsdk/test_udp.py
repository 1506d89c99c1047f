"""pymavlink as an autopilot on UDP (docs/src/deployment.md): `gimbal bridge` with its
MAVLink side on `udp:HOST:PORT` (the bridge knocks with an empty datagram until the
autopilot, listening like mavlink-router's `Mode = Server`, answers) and with a
telemetry link on `udp-listen:PORT` (the autopilot sends first, like MAVProxy's
`--out udp:`); the bridge answers the peer that spoke last; and each of its components
reports the version `gimbal --version` prints in AUTOPILOT_VERSION
(docs/src/firmware/configuration.md#versions)."""

import os
import re
import socket
import subprocess
import time
import unittest

from rig import GIMBAL, Process, free_port, wait_for

os.environ.setdefault("MAVLINK20", "1")
from pymavlink import mavutil  # noqa: E402
from pymavlink.dialects.v20 import common as mav  # noqa: E402


def version():
    """(flight_sw_version, flight_custom_version) that `gimbal --version` implies."""
    line = subprocess.run([str(GIMBAL), "--version"], capture_output=True, text=True,
                          check=True).stdout
    m = re.match(r"gimbal (\d+)\.(\d+)\.(\d+)(-\S+)? commit (\w+)(-dirty)?,", line)
    if m is None:
        raise AssertionError(f"gimbal --version: {line!r}")
    major, minor, patch = (int(m.group(i)) for i in (1, 2, 3))
    release = m.group(4) is None and m.group(6) is None
    sw = major << 24 | minor << 16 | patch << 8 | (255 if release else 0)
    commit = m.group(5)
    custom = commit[:8].encode() if commit != "unknown" else bytes(8)
    return sw, custom


class Autopilot:
    """A pymavlink autopilot (system 1, component 1) on one UDP socket."""

    def __init__(self, spec):
        self.conn = mavutil.mavlink_connection(spec, source_system=1, source_component=1)

    def heartbeat(self):
        self.conn.mav.heartbeat_send(mav.MAV_TYPE_QUADROTOR, mav.MAV_AUTOPILOT_ARDUPILOTMEGA,
                                     0, 0, mav.MAV_STATE_ACTIVE)

    def recv(self, what, predicate, timeout_s=10):
        """The first message `predicate` takes, sending a HEARTBEAT every second."""
        deadline = time.monotonic() + timeout_s
        last_hb = 0
        while time.monotonic() < deadline:
            if time.monotonic() - last_hb > 1:
                self.heartbeat()
                last_hb = time.monotonic()
            m = self.conn.recv_match(blocking=True, timeout=0.1)
            if m is not None and m.get_type() != "BAD_DATA" and predicate(m):
                return m
        raise AssertionError(f"no {what} within {timeout_s} s")

    def version_of(self, component, test):
        """AUTOPILOT_VERSION asked of `component` with MAV_CMD_REQUEST_MESSAGE."""
        self.conn.mav.command_long_send(1, component, mav.MAV_CMD_REQUEST_MESSAGE, 0,
                                        mav.MAVLINK_MSG_ID_AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0)
        ack = self.recv("COMMAND_ACK", lambda m: m.get_type() == "COMMAND_ACK" and
                        m.get_srcComponent() == component)
        test.assertEqual(ack.result, mav.MAV_RESULT_ACCEPTED)
        return self.recv("AUTOPILOT_VERSION", lambda m: m.get_type() == "AUTOPILOT_VERSION" and
                         m.get_srcComponent() == component)

    def close(self):
        self.conn.close()


class UdpTest(unittest.TestCase):
    def check_version(self, got):
        sw, custom = version()
        self.assertEqual(got.flight_sw_version, sw)
        self.assertEqual(bytes(got.flight_custom_version), custom)
        self.assertTrue(got.capabilities & mav.MAV_PROTOCOL_CAPABILITY_MAVLINK2)

    def test_mavlink_side_on_udp_knocks_then_answers_the_autopilot(self):
        port = free_port(socket.SOCK_DGRAM)
        ap = Autopilot(f"udpin:127.0.0.1:{port}")
        bridge = Process("bridge", [str(GIMBAL), "bridge", "--fc", "mavlink",
                                    "--fc-port", f"udp:127.0.0.1:{port}", "--pod-port", "sim",
                                    "--events", "json", "--seconds", "60"])
        try:
            hb = ap.recv("HEARTBEAT of the gimbal", lambda m: m.get_type() == "HEARTBEAT" and
                         m.get_srcComponent() == 154, 15)
            self.assertEqual(hb.get_srcSystem(), 1)
            for component in (154, 100):
                self.check_version(ap.version_of(component, self))
        except AssertionError as e:
            raise AssertionError(f"{e}\n--- bridge ---\n{bridge.tail()}") from None
        finally:
            bridge.stop()
            ap.close()

    def test_telemetry_link_listens_and_follows_the_last_speaker(self):
        bridge = Process("bridge", [str(GIMBAL), "bridge", "--fc", "siyi", "--fc-port", "sim",
                                    "--pod-port", "sim", "--telemetry-port",
                                    "udp-listen:127.0.0.1:0", "--events", "json",
                                    "--seconds", "60"])
        aps = []
        try:
            listening = wait_for("port_listening", lambda: bridge.events("port_listening"), 15)
            port = int(listening[0]["address"].rsplit(":", 1)[1])
            first = Autopilot(f"udpout:127.0.0.1:{port}")
            aps.append(first)
            first.recv("HEARTBEAT of 158", lambda m: m.get_type() == "HEARTBEAT" and
                       m.get_srcComponent() == 158, 15)
            self.check_version(first.version_of(158, self))
            # Another socket speaks: the bridge answers it from now on.
            second = Autopilot(f"udpout:127.0.0.1:{port}")
            aps.append(second)
            second.recv("HEARTBEAT of 158 at the new peer", lambda m: m.get_type() ==
                        "HEARTBEAT" and m.get_srcComponent() == 158, 15)
            peers = [e["peer"] for e in bridge.events("port_peer")]
            self.assertGreaterEqual(len(set(peers)), 2, peers)
        except AssertionError as e:
            raise AssertionError(f"{e}\n--- bridge ---\n{bridge.tail()}") from None
        finally:
            bridge.stop()
            for ap in aps:
                ap.close()


if __name__ == "__main__":
    unittest.main()
