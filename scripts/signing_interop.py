#!/usr/bin/env python3
"""MAVLink 2 signing against pymavlink's own implementation (docs/src/security.md).

Runs `gimbal bridge --fc mavlink --fc-port tcp-listen:127.0.0.1:0 --pod-port sim
--signing require --signing-key-file KEY` and plays the autopilot over TCP with
pymavlink 2.4.50, signing with the same key:

1. pymavlink's signed HEARTBEAT (system 1, an ArduPilot quadrotor) is taken: the bridge
   introduces its gimbal (component 154) and camera (100), and every frame it sends
   checks with pymavlink's signing (pymavlink refuses unsigned or badly signed frames
   here), its timestamps increasing.
2. A signed COMMAND_LONG REQUEST_MESSAGE(GIMBAL_DEVICE_INFORMATION) from pymavlink is
   taken (sent again every second while the pod is not known yet, as the autopilots do):
   ACK accepted, then the message, signed.
3. The same command unsigned, then signed with another key, are refused: no ACK, and
   the bridge reports `refused` events (`unsigned`, `bad_signature`).

Usage: signing_interop.py GIMBAL_BINARY
"""

import hashlib
import json
import os
import subprocess
import sys
import tempfile
import threading
import time

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402
from pymavlink.dialects.v20 import common as mav  # noqa: E402

KEY = hashlib.sha256(b"k40t bridge signing interop").digest()
WRONG = hashlib.sha256(b"not the key").digest()


def fail(msg):
    print(f"signing-interop: FAILED: {msg}")
    sys.exit(1)


def main():
    gimbal = sys.argv[1]
    with tempfile.TemporaryDirectory() as d:
        key_file = os.path.join(d, "key.hex")
        with open(key_file, "w") as f:
            f.write(KEY.hex() + "\n")
        bridge = subprocess.Popen(
            [gimbal, "bridge", "--fc", "mavlink", "--fc-port", "tcp-listen:127.0.0.1:0",
             "--pod-port", "sim", "--signing", "require", "--signing-key-file", key_file,
             "--events", "json", "--seconds", "40"],
            stdout=subprocess.PIPE, text=True)
        events = []
        port = None
        while port is None:
            line = bridge.stdout.readline()
            if not line:
                fail("the bridge ended before listening")
            e = json.loads(line)
            events.append(e)
            if e.get("event") == "port_listening":
                port = int(e["address"].rsplit(":", 1)[1])

        def read_events():
            for line in bridge.stdout:
                try:
                    events.append(json.loads(line))
                except ValueError:
                    pass
        threading.Thread(target=read_events, daemon=True).start()

        conn = mavutil.mavlink_connection(f"tcp:127.0.0.1:{port}", source_system=1,
                                          source_component=1)
        m = conn.mav
        m.signing.secret_key = KEY
        m.signing.link_id = 0
        m.signing.timestamp = int((time.time() - 1420070400) * 100000)
        m.signing.sign_outgoing = True
        m.signing.allow_unsigned_callback = None

        def heartbeat():
            m.heartbeat_send(mav.MAV_TYPE_QUADROTOR, mav.MAV_AUTOPILOT_ARDUPILOTMEGA, 0, 0,
                             mav.MAV_STATE_ACTIVE)

        def request_info():
            m.command_long_send(1, 154, mav.MAV_CMD_REQUEST_MESSAGE, 0, 283, 0, 0, 0, 0, 0, 0)

        def collect(seconds, want=None):
            got = []
            end = time.time() + seconds
            last_hb = 0
            while time.time() < end:
                if time.time() - last_hb > 1:
                    heartbeat()
                    last_hb = time.time()
                msg = conn.recv_match(blocking=True, timeout=0.1)
                if msg is None:
                    continue
                if msg.get_type() == "BAD_DATA":
                    fail(f"pymavlink refused a frame of the bridge: {msg}")
                got.append(msg)
                if want and want(got):
                    break
            return got

        # 1. The bridge takes the signed heartbeat and introduces itself, signed.
        got = collect(8, lambda g: any(x.get_type() == "HEARTBEAT" and
                                       x.get_srcComponent() == 100 for x in g))
        comps = {x.get_srcComponent() for x in got if x.get_type() == "HEARTBEAT"}
        if not {154, 100} <= comps:
            fail(f"no signed heartbeat of the gimbal and camera: {comps}")
        unsigned = [x for x in got if not x._signed]
        if unsigned:
            fail(f"unsigned frames from the bridge: {unsigned[:3]}")
        print(f"signing-interop: {len(got)} signed frames of the bridge checked by pymavlink")

        # 2. A signed command is taken. Until the pod has told its versions the bridge
        # answers TEMPORARILY_REJECTED, and the request is sent again every second, as
        # ArduPilot and PX4 do.
        got = []
        for _ in range(15):
            request_info()
            got = collect(1.2, lambda g: any(x.get_type() == "GIMBAL_DEVICE_INFORMATION"
                                             for x in g))
            if any(x.get_type() == "GIMBAL_DEVICE_INFORMATION" for x in got):
                break
        acks = [x for x in got if x.get_type() == "COMMAND_ACK" and
                x.command == mav.MAV_CMD_REQUEST_MESSAGE]
        if not acks or acks[-1].result != mav.MAV_RESULT_ACCEPTED:
            fail(f"the signed command was not accepted: {[a.result for a in acks]}")
        if not any(x.get_type() == "GIMBAL_DEVICE_INFORMATION" for x in got):
            fail("no GIMBAL_DEVICE_INFORMATION after the signed request")
        if any(not x._signed for x in got):
            fail("unsigned frames from the bridge")
        print("signing-interop: pymavlink's signed COMMAND_LONG accepted, answered signed")

        # 3. Unsigned, then with another key: refused, reported.
        m.signing.sign_outgoing = False
        request_info()
        m.signing.sign_outgoing = True
        m.signing.secret_key = WRONG
        request_info()
        m.signing.secret_key = KEY
        got = collect(3)
        acks = [x for x in got if x.get_type() == "COMMAND_ACK" and
                x.command == mav.MAV_CMD_REQUEST_MESSAGE]
        if acks:
            fail(f"an unsigned or forged command was answered: {acks}")
        time.sleep(0.5)
        reasons = [e.get("reason") for e in events if e.get("event") == "refused"]
        if "unsigned" not in reasons or "bad_signature" not in reasons:
            fail(f"the refusals were not reported: {reasons}")
        print(f"signing-interop: unsigned and forged commands refused ({reasons})")
        bridge.terminate()
        bridge.wait(10)
        print("signing-interop: passed")


if __name__ == "__main__":
    main()
