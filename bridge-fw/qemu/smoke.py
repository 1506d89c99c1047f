#!/usr/bin/env python3
"""Smoke test of the emulated bridge firmware (Python 3 standard library only).

scripts/qemu-smoke starts QEMU's b-l475e-iot01a with the `qemu` flavour of the firmware,
UART4 (FC) and USART2 (pod) on Unix sockets and the GPIO write trace in a file; this
script then checks, acting as the pod:
  - the firmware boots (its semihosting line on QEMU's stdout, FC protocol named),
  - the bridge probes the silent pod with valid K40T frames (0x000018 gimbal version,
    CRC checked),
  - attitude reports from the pod bring the link up: the bridge asks both versions
    (0x000018 and 0x000317) at once,
  - garbage from the FC is survived, LED2 (PB14) blinks.
Emulated time runs slower than wall time on a busy host: generous time-outs, no timing
assertions. Prints one line per check and `N passed, M failed`.
"""

import argparse
import os
import re
import socket
import struct
import zlib
import sys
import time

TIMEOUT = float(os.environ.get("BRIDGE_TEST_TIMEOUT", "60"))
GIMBAL_VERSION, CAMERA_VERSION, ATTITUDE = 0x000018, 0x000317, 0x000002


def crc_mcrf4xx(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0x8408 if crc & 1 else crc >> 1
    return crc


def k40t_frame(msg_id, payload, dst=(0x02, 0x01), src=(0x03, 0x01), seq=0):
    body = bytes([len(payload), *dst, seq & 0xFF, *src]) + msg_id.to_bytes(3, "little") + payload
    return b"\xfd" + body + crc_mcrf4xx(body).to_bytes(2, "little")


class K40tReader:
    """Splits the byte stream from the bridge into K40T frames, checking each CRC."""

    def __init__(self):
        self.buf = b""
        self.bad = 0

    def push(self, data):
        self.buf += data
        frames = []
        while True:
            start = self.buf.find(b"\xfd")
            if start < 0:
                self.bad += len(self.buf)
                self.buf = b""
                break
            self.bad += start
            self.buf = self.buf[start:]
            if len(self.buf) < 12 or len(self.buf) < 12 + self.buf[1]:
                break
            n = 12 + self.buf[1]
            frame, self.buf = self.buf[:n], self.buf[n:]
            if crc_mcrf4xx(frame[1:-2]) != int.from_bytes(frame[-2:], "little"):
                self.bad += n
                continue
            frames.append(frame)
        return frames


def msg_id(frame):
    return int.from_bytes(frame[7:10], "little")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--fc", required=True)
    ap.add_argument("--pod", required=True)
    ap.add_argument("--update", required=True)
    ap.add_argument("--trace", required=True)
    ap.add_argument("--qemu-out", required=True)
    ap.add_argument("--qemu-pid", type=int, required=True)
    args = ap.parse_args()
    results = []

    def check(name, ok, detail=""):
        results.append(ok)
        print(f"{'PASS' if ok else 'FAIL'} {name}{': ' + detail if detail else ''}", flush=True)
        return ok

    def alive():
        try:
            os.kill(args.qemu_pid, 0)
            return True
        except OSError:
            return False

    def connect(path):
        deadline = time.time() + TIMEOUT
        while True:
            try:
                s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                s.connect(path)
                s.settimeout(0.2)
                return s
            except OSError:
                if time.time() > deadline:
                    raise
                time.sleep(0.1)

    pod = connect(args.pod)
    fc = connect(args.fc)
    reader = K40tReader()

    def frames_until(pred, timeout):
        deadline = time.time() + timeout
        seen = []
        while time.time() < deadline and alive():
            try:
                data = pod.recv(4096)
            except socket.timeout:
                continue
            # Every frame of this read is kept, even past the one that satisfies `pred`.
            seen.extend(reader.push(data))
            if pred(seen):
                return seen
        return seen

    deadline = time.time() + TIMEOUT
    boot = ""
    while time.time() < deadline and "up, HCLK" not in boot:
        time.sleep(0.2)
        with open(args.qemu_out, errors="replace") as f:
            boot = f.read()
    line = next((l for l in boot.splitlines() if "bridge-fw" in l), "")
    check("boots", "up, HCLK" in boot, line)
    lines = boot.splitlines()
    first = lines[0] if lines else ""
    check("through the bootloader (its line first, the active slot at 0x0800a000)",
          first == "bootloader: boot, active slot at 0x0800a000", first)

    # The console on the update port (USART3 here; docs/src/console.md): a command typed
    # is echoed and answered, a setting saved to the store (a RAM model on QEMU).
    update = connect(args.update)

    def console(line):
        update.sendall(line.encode() + b"\r")
        text, deadline = "", time.time() + TIMEOUT
        while time.time() < deadline and alive() and not (
                text.endswith("> ") and ("\nok" in text or "\nerror" in text)):
            try:
                text += update.recv(1024).decode(errors="replace")
            except socket.timeout:
                pass
        return text

    answer = console("version")
    check("the console answers version with the build's line",
          re.match(r"version\r\n\d+\.\d+\.\d+\S* commit \w+", answer) is not None
          and "qemu: fc-siyi" in answer and "\r\nok\r\n> " in answer,
          repr(answer))
    answer = console("set leap_seconds 19") + console("save")
    check("the console sets and saves a setting", "ok: 1 settings kept" in answer, repr(answer))

    # The update protocol on the same port: an update frame at a line's start hands it
    # over. Hello is answered with Info (bridge_update::wire).
    hello = b"\x01\x00\x00"
    update.sendall(b"\xb7\x4d" + hello + struct.pack("<I", zlib.crc32(hello)))
    info, deadline = b"", time.time() + TIMEOUT
    def complete(b):
        return len(b) >= 9 and len(b) >= 9 + struct.unpack("<H", b[3:5])[0]
    while time.time() < deadline and alive() and not complete(info):
        try:
            info += update.recv(256)
        except socket.timeout:
            pass
    ok = len(info) >= 23 and info[:3] == b"\xb7\x4d\x81"
    if ok:
        n = struct.unpack("<H", info[3:5])[0]
        ok = len(info) >= 9 + n and zlib.crc32(info[2:5 + n]) == struct.unpack("<I", info[5 + n:9 + n])[0]
        state, slot = info[5], struct.unpack("<I", info[6:10])[0]
        version = info[19:5 + n].decode(errors="replace")
        ok = ok and state == 0 and slot == 482 * 1024 and "qemu" in version
        detail = f"version {version!r}, state {state}, slot {slot} B"
    else:
        detail = info.hex()
    check("the update port answers Hello with the version, a confirmed image and the slot size", ok, detail)

    seen = frames_until(lambda s: any(msg_id(f) == GIMBAL_VERSION for f in s), TIMEOUT)
    probe = next((f for f in seen if msg_id(f) == GIMBAL_VERSION), None)
    check("probes the silent pod (0x000018, valid CRC)", probe is not None and reader.bad == 0,
          probe.hex() if probe else f"{len(seen)} frames, {reader.bad} bad bytes")

    # Act as the pod: attitude reports at 10 Hz until both version queries have come.
    asked = set()
    deadline = time.time() + TIMEOUT
    seq = 0
    while time.time() < deadline and asked != {GIMBAL_VERSION, CAMERA_VERSION} and alive():
        seq += 1
        pod.sendall(k40t_frame(ATTITUDE, bytes(20), seq=seq))
        fc.sendall(b"\x55\x66garbage\x00\xff" * 3)
        for f in frames_until(lambda s: True, 0.1):
            if msg_id(f) in (GIMBAL_VERSION, CAMERA_VERSION) and f[5:7] == b"\x02\x01":
                asked.add(msg_id(f))
    check("reports bring the link up: both versions asked", asked == {GIMBAL_VERSION, CAMERA_VERSION},
          f"asked {sorted(hex(a) for a in asked)}")
    check("frames from the bridge all valid", reader.bad == 0, f"{reader.bad} bad bytes")

    with open(args.trace, errors="replace") as f:
        led = sum(1 for l in f if "stm32l4x5_gpio_write GPIOB" in l)
    check("LED2 blinks (GPIOB writes traced)", led >= 2, f"{led} writes")
    check("still running (no fault, no panic)", alive())

    passed = sum(results)
    print(f"qemu smoke: {passed} passed, {len(results) - passed} failed")
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
