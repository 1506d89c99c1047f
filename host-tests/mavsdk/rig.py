"""The real-client rig: the bridge (`gimbal bridge --fc mavlink`, the real runner on the
host's clock, the simulated pod in its process) on a TCP port of a simulated autopilot
(`gimbal sim-fc mavlink`: PX4 or ArduPilot, routing as they route), whose ground link is
a UDP port the ground app listens on: MAVSDK (`Rig.start()`), or pymavlink where MAVSDK
has no API (`Rig.start(client="pymavlink")`, then `rig.mav`). The simulated autopilot
answers where the ground app's datagrams come from: one client per rig (see
docs/src/testing.md).

One rig per test module (`Rig.start()` in `setUpModule`); every wait is bounded.
"""

import json
import os
import socket
import subprocess
import tempfile
import threading
import time
from pathlib import Path

import mavsdk
from mavsdk import ComponentType, Configuration, Mavsdk

# pymavlink: MAVLink 2 and the common dialect (camera and gimbal ids are above 255).
os.environ.setdefault("MAVLINK20", "1")
os.environ.setdefault("MAVLINK_DIALECT", "common")

ROOT = Path(__file__).resolve().parents[2]
GIMBAL = Path(os.environ.get("GIMBAL_BIN", ROOT / "target" / "debug" / "gimbal"))
CAMERA = 100
GIMBAL_COMPONENT = 154


def free_port(kind=socket.SOCK_STREAM):
    """A port the kernel says is free on 127.0.0.1 (TCP or UDP)."""
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(what, predicate, timeout_s, step_s=0.05):
    """Polls `predicate` until it returns a true value (returned) or `timeout_s` passes
    (AssertionError naming `what`)."""
    deadline = time.monotonic() + timeout_s
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            raise AssertionError(f"timed out after {timeout_s} s waiting for {what}")
        time.sleep(step_s)


def attempt(call):
    """`call()`, or None when it raises (a MAVSDK getter before the value is known)."""
    try:
        return call()
    except Exception:  # noqa: BLE001 (any MAVSDK error means "not yet")
        return None


class Process:
    """A child process printing JSON lines, kept as they come (a reader thread)."""

    def __init__(self, name, args):
        self.name = name
        self.args = args
        self.lines = []
        self.lock = threading.Lock()
        self.proc = subprocess.Popen(
            args,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            bufsize=1,
        )
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.proc.stdout:
            with self.lock:
                self.lines.append(line.rstrip("\n"))

    def events(self, name=None):
        """The JSON events printed so far (those named `name`)."""
        out = []
        with self.lock:
            lines = list(self.lines)
        for line in lines:
            try:
                e = json.loads(line)
            except ValueError:
                continue
            if name is None or e.get("event") == name:
                out.append(e)
        return out

    def tail(self, n=40):
        with self.lock:
            return "\n".join(self.lines[-n:])

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=5)


class Rig:
    """The bridge, the simulated autopilot and a MAVSDK ground station."""

    def __init__(self, autopilot="px4", sim_args=(), bridge_args=()):
        self.autopilot = autopilot
        self.sim_args = list(sim_args)
        self.bridge_args = list(bridge_args)
        self.sim = None
        self.bridge = None
        self.mavsdk = None
        self.system = None
        self.mav = None

    def start(self, timeout_s=20, client="mavsdk"):
        if not GIMBAL.exists():
            raise RuntimeError(f"{GIMBAL} missing: build it (cargo build -p gimbal)")
        fc_port = free_port()
        self.gcs_port = free_port(socket.SOCK_DGRAM)
        self.sim = Process(
            "sim-fc",
            [str(GIMBAL), "sim-fc", "mavlink", "--autopilot", self.autopilot,
             "--port", f"tcp-listen:127.0.0.1:{fc_port}",
             "--gcs", f"udp:127.0.0.1:{self.gcs_port}", *self.sim_args],
        )
        # A state directory of the rig's own: what a test sets (PARAM_SET, signing
        # timestamps) is kept there, never in the user's, and never reaches another rig.
        self.state_dir = tempfile.TemporaryDirectory(prefix="bridge-rig-")
        self.bridge = Process(
            "bridge",
            [str(GIMBAL), "bridge", "--fc", "mavlink",
             "--fc-port", f"tcp:127.0.0.1:{fc_port}", "--pod-port", "sim",
             "--events", "json", "--state-dir", self.state_dir.name, *self.bridge_args],
        )
        if client == "pymavlink":
            from pymavlink import mavutil

            # As a ground station: system 255, component 190.
            self.mav = mavutil.mavlink_connection(
                f"udpin:127.0.0.1:{self.gcs_port}", source_system=255, source_component=190)
            hb = self.mav.wait_heartbeat(timeout=timeout_s)
            if hb is None:
                raise AssertionError(self.report("no HEARTBEAT within the time-out"))
            return self
        config = Configuration.create_with_component_type(ComponentType.GROUND_STATION)
        self.mavsdk = Mavsdk(config)
        result = self.mavsdk.add_any_connection(f"udpin://127.0.0.1:{self.gcs_port}")
        if result != mavsdk.ConnectionResult.SUCCESS:
            raise RuntimeError(f"MAVSDK connection: {result}")
        self.system = self.mavsdk.first_autopilot(timeout_s)
        if self.system is None:
            raise AssertionError(self.report("no autopilot within the time-out"))
        return self

    def components(self):
        return set(self.system.component_ids())

    def report(self, what):
        """`what`, with the tails of both processes' output."""
        return (f"{what}\n--- sim-fc ---\n{self.sim.tail()}\n"
                f"--- bridge ---\n{self.bridge.tail()}")

    def stop(self):
        # The client first, then the bridge and the autopilot: MAVSDK 4.1 was seen to die
        # by SIGSEGV in one of its own threads when the system it holds cameras of went
        # away under it (the bridge stopped first, two Camera plugins of the system
        # alive; docs/src/testing.md, "Real clients").
        if self.mavsdk is not None:
            self.mavsdk.destroy()
            self.mavsdk = None
        if self.mav is not None:
            self.mav.close()
            self.mav = None
        for p in (self.bridge, self.sim):
            if p is not None:
                p.stop()

    def recv(self, msg_type, predicate=lambda m: True, timeout_s=10):
        """pymavlink: the next message of `msg_type` that `predicate` accepts (bounded)."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            m = self.mav.recv_match(type=msg_type, blocking=True, timeout=0.2)
            if m is not None and predicate(m):
                return m
        raise AssertionError(self.report(f"no {msg_type} within {timeout_s} s"))

    def pod_photos(self):
        """Photos the simulated pod took (its `sim_pod_photo` events)."""
        return self.bridge.events("sim_pod_photo")
