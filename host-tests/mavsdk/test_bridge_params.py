"""The bridge's own parameters (docs/src/firmware/configuration.md, "Settings") through
pymavlink as the ground station: PARAM_REQUEST_LIST, PARAM_REQUEST_READ and PARAM_SET to
the bridge's component, answered with PARAM_VALUE; on the MAVLink side (component 154,
behind an ArduPilot: values as a C cast) and on the telemetry link (component 158,
behind a PX4: values byte-wise). A pymavlink autopilot on UDP, as in test_udp; each
bridge keeps its settings in a state directory of its own."""

import os
import socket
import struct
import tempfile
import time
import unittest

from rig import GIMBAL, Process, free_port, wait_for

os.environ.setdefault("MAVLINK20", "1")
from pymavlink import mavutil  # noqa: E402
from pymavlink.dialects.v20 import common as mav  # noqa: E402

# The ground station's ids (the bridge's default gcs_ids take 255).
GCS = (255, 190)
INT_TYPES = {mav.MAV_PARAM_TYPE_INT8, mav.MAV_PARAM_TYPE_INT16, mav.MAV_PARAM_TYPE_INT32}


def name_of(m):
    n = m.param_id
    return n.rstrip("\x00") if isinstance(n, str) else bytes(n).rstrip(b"\x00").decode()


class Link:
    """A pymavlink autopilot (1/1, heartbeats of `autopilot`) and a ground station (255/190)
    on one UDP socket; values encoded as `autopilot` encodes them."""

    def __init__(self, spec, autopilot):
        self.conn = mavutil.mavlink_connection(spec, source_system=1, source_component=1)
        self.gcs = mav.MAVLink(self.conn, srcSystem=GCS[0], srcComponent=GCS[1])
        self.autopilot = autopilot
        self.bytewise = autopilot == mav.MAV_AUTOPILOT_PX4
        self.last_hb = 0

    def decode(self, m):
        """A PARAM_VALUE's value as a number."""
        if not self.bytewise:
            return m.param_value
        fmt = "<i" if m.param_type in INT_TYPES else "<I"
        return struct.unpack(fmt, struct.pack("<f", m.param_value))[0]

    def encode(self, value, param_type):
        if not self.bytewise:
            return float(value)
        fmt = "<i" if param_type in INT_TYPES else "<I"
        return struct.unpack("<f", struct.pack(fmt, value))[0]

    def recv(self, what, predicate, timeout_s=10):
        """The first message `predicate` takes, a HEARTBEAT every second meanwhile."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if time.monotonic() - self.last_hb > 1:
                self.conn.mav.heartbeat_send(mav.MAV_TYPE_QUADROTOR, self.autopilot, 0, 0,
                                             mav.MAV_STATE_ACTIVE)
                self.last_hb = time.monotonic()
            m = self.conn.recv_match(blocking=True, timeout=0.1)
            if m is not None and m.get_type() != "BAD_DATA" and predicate(m):
                return m
        raise AssertionError(f"no {what} within {timeout_s} s")

    def value(self, component, what, predicate=lambda m: True):
        return self.recv(what, lambda m: m.get_type() == "PARAM_VALUE" and
                         m.get_srcComponent() == component and predicate(m))

    def close(self):
        self.conn.close()


class BridgeParamsTest(unittest.TestCase):
    def exercise(self, link, component, name, default, new):
        """List, read, set, and a refused set of parameter `name` (`default` -> `new`)."""
        link.recv(f"HEARTBEAT of {component}", lambda m: m.get_type() == "HEARTBEAT" and
                  m.get_srcComponent() == component, 15)
        link.gcs.param_request_list_send(1, component)
        first = link.value(component, "the first PARAM_VALUE")
        values = {first.param_index: first}
        while len(values) < first.param_count:
            m = link.value(component, f"PARAM_VALUE {len(values)} of {first.param_count}")
            values[m.param_index] = m
        names = [name_of(values[i]) for i in sorted(values)]
        self.assertEqual(sorted(values), list(range(first.param_count)))
        self.assertTrue(all(n.startswith("BRG_") and len(n) <= 16 for n in names), names)
        self.assertEqual(len(set(names)), len(names))
        self.assertIn(name, names)

        link.gcs.param_request_read_send(1, component, name.encode(), -1)
        read = link.value(component, f"{name} read", lambda m: name_of(m) == name)
        self.assertEqual(link.decode(read), default)
        by_index = names.index(name)
        link.gcs.param_request_read_send(1, component, b"", by_index)
        again = link.value(component, f"{name} by index", lambda m: name_of(m) == name)
        self.assertEqual(again.param_index, by_index)

        link.gcs.param_set_send(1, component, name.encode(),
                                link.encode(new, read.param_type), read.param_type)
        done = link.value(component, f"{name} set", lambda m: name_of(m) == name)
        self.assertEqual(link.decode(done), new)
        # Out of range: the value as it is, and a STATUSTEXT saying why.
        link.gcs.param_set_send(1, component, name.encode(),
                                link.encode(100_000, read.param_type), read.param_type)
        seen = {}
        link.recv(f"{name} refused: PARAM_VALUE and STATUSTEXT", lambda m: (
            m.get_srcComponent() == component and (
                (m.get_type() == "PARAM_VALUE" and name_of(m) == name and
                 seen.setdefault("value", m)) or
                (m.get_type() == "STATUSTEXT" and seen.setdefault("text", m))) and
            len(seen) == 2))
        self.assertEqual(link.decode(seen["value"]), new)
        self.assertIn(name, seen["text"].text)
        self.assertIn("out of range", seen["text"].text)

    def test_mavlink_side_behind_ardupilot(self):
        port = free_port(socket.SOCK_DGRAM)
        link = Link(f"udpin:127.0.0.1:{port}", mav.MAV_AUTOPILOT_ARDUPILOTMEGA)
        with tempfile.TemporaryDirectory() as state:
            bridge = Process("bridge", [str(GIMBAL), "bridge", "--fc", "mavlink",
                                        "--fc-port", f"udp:127.0.0.1:{port}",
                                        "--pod-port", "sim", "--state-dir", state,
                                        "--events", "json", "--seconds", "60"])
            try:
                self.exercise(link, 154, "BRG_LEAP_SEC", 18, 19)
                settings = bridge.events("setting")
                self.assertTrue(any(e.get("outcome") == "applied" for e in settings), settings)
            except AssertionError as e:
                raise AssertionError(f"{e}\n--- bridge ---\n{bridge.tail()}") from None
            finally:
                bridge.stop()
                link.close()

    def test_telemetry_link_behind_px4(self):
        with tempfile.TemporaryDirectory() as state:
            bridge = Process("bridge", [str(GIMBAL), "bridge", "--fc", "siyi",
                                        "--fc-port", "sim", "--pod-port", "sim",
                                        "--telemetry-port", "udp-listen:127.0.0.1:0",
                                        "--state-dir", state, "--events", "json",
                                        "--seconds", "60"])
            link = None
            try:
                listening = wait_for("port_listening",
                                     lambda: bridge.events("port_listening"), 15)
                port = int(listening[0]["address"].rsplit(":", 1)[1])
                link = Link(f"udpout:127.0.0.1:{port}", mav.MAV_AUTOPILOT_PX4)
                self.exercise(link, 158, "BRG_LEAP_SEC", 18, 20)
            except AssertionError as e:
                raise AssertionError(f"{e}\n--- bridge ---\n{bridge.tail()}") from None
            finally:
                bridge.stop()
                if link is not None:
                    link.close()


if __name__ == "__main__":
    unittest.main()
