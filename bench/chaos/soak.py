#!/usr/bin/env python3
"""soak.py: `rangekit serve` with MQTT over emulators for a stated time, under churn.

Meanwhile: SSE clients come and go, one stays for the whole run and notes every link event,
the broker restarts every --broker-every seconds, an emulator is SIGKILLed (and started again
on the same path) every --kill-every seconds, a capture of every sensor runs throughout, and
each capture format is downloaded in parallel every --download-every seconds.

Reports, as text and as JSON (--report): RSS, descriptors and threads of the service at the
start, after the warm-up (--warmup, 10 min) and at the end; the largest /healthz time; lost
records; each outage seen as disconnected then reconnected; the MQTT session after each broker
restart; the capture's integrity at the end. Exit 1 when a goal is missed:
RSS and descriptors flat (their median over the last ten minutes within 10 % of their median
over the ten minutes after the warm-up), 0 records lost, every
outage seen, every download whole, the capture intact.

    python3 bench/chaos/soak.py --build build --minutes 120 --report soak.json
"""

import argparse
import json
import os
import random
import signal
import socket
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import cli_path, stop  # noqa: E402

# What a running capture downloads as (sqlite once it is stopped; the .log layout is the ULS
# Interface Program's and refused for a capture with an LS5).
FORMATS = ("csv", "jsonl")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(predicate, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.1)  # polling a condition with a deadline
    raise RuntimeError(f"timed out waiting for {what}")


class Broker:
    """mosquitto on a loopback port of its own, started again on the same port."""

    def __init__(self, folder):
        self.port = free_port()
        self.conf = os.path.join(folder, "mosquitto.conf")
        with open(self.conf, "w", encoding="utf-8") as f:
            f.write(f"listener {self.port} 127.0.0.1\nallow_anonymous true\npersistence false\n")
        self.log = open(os.path.join(folder, "mosquitto.log"), "a", encoding="utf-8")
        self.proc = None

    def start(self):
        self.proc = subprocess.Popen(["mosquitto", "-c", self.conf], stdout=self.log, stderr=self.log)

        def listening():
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=0.5).close()
                return True
            except OSError:
                return False

        wait_until(listening, 10, "mosquitto to listen")

    def stop(self):
        if self.proc:
            stop(self.proc)


class Subscriber:
    """mosquitto_sub on the service's topics, counting messages; started again after each broker restart."""

    def __init__(self, port):
        self.port = port
        self.count = 0
        self.since_start = 0  # what this instance heard: after a broker restart, proof of a new session
        self.lock = threading.Lock()
        self.proc = None

    def start(self):
        with self.lock:
            self.since_start = 0
        self.proc = subprocess.Popen(["mosquitto_sub", "-h", "127.0.0.1", "-p", str(self.port), "-t", "rangekit/#"],
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        threading.Thread(target=self._read, args=(self.proc,), daemon=True).start()

    def _read(self, proc):
        for _ in proc.stdout:
            with self.lock:
                if proc is not self.proc:
                    break
                self.count += 1
                self.since_start += 1

    def messages(self):
        with self.lock:
            return self.count

    def heard_since_start(self):
        with self.lock:
            return self.since_start

    def stop(self):
        if self.proc:
            stop(self.proc)


class Emulator:
    def __init__(self, cli, args, name):
        self.cli, self.args, self.name = cli, args, name
        self.proc = None

    def start(self):
        self.proc = subprocess.Popen([self.cli, "sim"] + self.args, stdout=subprocess.PIPE,
                                     stderr=subprocess.DEVNULL, text=True, start_new_session=True)
        line = self.proc.stdout.readline()
        if "ready" not in line:
            raise RuntimeError(f"{self.name} emulator did not start: {line!r}")

    def kill(self):
        self.proc.kill()
        self.proc.wait()


class Service:
    def __init__(self, cli, site, folder):
        self.port = free_port()
        self.base = f"http://127.0.0.1:{self.port}"
        self.log = open(os.path.join(folder, "serve.log"), "a", encoding="utf-8")
        self.proc = subprocess.Popen([cli, "serve", "--config", site, "--listen", f"127.0.0.1:{self.port}"],
                                     stdout=self.log, stderr=self.log)

    def request(self, method, path, body=None, timeout=30):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"} if data else {})
        with urllib.request.urlopen(req, timeout=timeout) as reply:
            return reply.status, reply.headers, reply.read()

    def healthy(self):
        try:
            return self.request("GET", "/healthz", timeout=1)[0] == 200
        except (OSError, urllib.error.URLError):
            return False

    def process_figures(self):
        status = {}
        with open(f"/proc/{self.proc.pid}/status", encoding="utf-8") as f:
            for line in f:
                key, _, value = line.partition(":")
                status[key] = value.strip()
        return {"rss_kb": int(status["VmRSS"].split()[0]), "threads": int(status["Threads"]),
                "fds": len(os.listdir(f"/proc/{self.proc.pid}/fd"))}

    def metrics(self):
        text = self.request("GET", "/metrics")[2].decode()
        values = {}
        for line in text.splitlines():
            if line and not line.startswith("#"):
                name, _, value = line.rpartition(" ")
                values[name] = float(value)
        return values


class EventWatcher:
    """One SSE client for the whole run: the link events of each sensor, in order."""

    def __init__(self, service):
        self.events = []  # (monotonic time, sensor, kind)
        self.samples = 0
        self.lock = threading.Lock()
        self.stopping = False
        self.sock = socket.create_connection(("127.0.0.1", service.port))
        self.sock.sendall(f"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:{service.port}\r\n\r\n".encode())
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        pending = b""
        while not self.stopping:
            try:
                chunk = self.sock.recv(65536)
            except OSError:
                break
            if not chunk:
                break
            pending += chunk
            while b"\n\n" in pending:
                block, pending = pending.split(b"\n\n", 1)
                for line in block.split(b"\n"):
                    if not line.startswith(b"data: "):
                        continue
                    try:
                        item = json.loads(line[6:])
                    except json.JSONDecodeError:
                        continue
                    with self.lock:
                        if item.get("type") == "sample":
                            self.samples += 1
                        elif item.get("type") == "event":
                            self.events.append((time.monotonic(), item.get("sensor"), item["data"].get("event")))

    def between(self, since, until, sensor):
        with self.lock:
            return [kind for (at, name, kind) in self.events
                    if at >= since and (until is None or at < until) and name == sensor]

    def close(self):
        self.stopping = True
        self.sock.close()


def churn_client(service, seconds, results):
    """An SSE client that reads for a while and goes; counts what it got."""
    try:
        sock = socket.create_connection(("127.0.0.1", service.port), timeout=5)
        sock.sendall(f"GET /api/events?max_rate={random.choice([1, 10, 50])} HTTP/1.1\r\n"
                     f"Host: 127.0.0.1:{service.port}\r\n\r\n".encode())
        got = 0
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            chunk = sock.recv(65536)
            if not chunk:
                break
            got += len(chunk)
        sock.close()
        results.append(got > 0)
    except OSError:
        results.append(False)


def download_all(service, capture, results):
    def one(fmt):
        try:
            status, headers, body = service.request("GET", f"/api/captures/{capture}/download?format={fmt}",
                                                    timeout=120)
            results.append(status == 200 and int(headers["Content-Length"]) == len(body))
        except (OSError, urllib.error.URLError, KeyError, ValueError):
            results.append(False)

    threads = [threading.Thread(target=one, args=(fmt,)) for fmt in FORMATS]
    for t in threads:
        t.start()
    for t in threads:
        t.join()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--minutes", type=float, default=120)
    parser.add_argument("--warmup", type=float, default=600, help="seconds before the baseline figures")
    parser.add_argument("--broker-every", type=float, default=600)
    parser.add_argument("--kill-every", type=float, default=300)
    parser.add_argument("--download-every", type=float, default=180)
    parser.add_argument("--sample-every", type=float, default=30)
    parser.add_argument("--report", help="write the figures as JSON here")
    args = parser.parse_args()
    cli = cli_path(args.build)
    random.seed(1)
    folder = tempfile.mkdtemp(prefix="rangekit-soak-")
    broker = Broker(folder)
    broker.start()
    subscriber = Subscriber(broker.port)
    subscriber.start()
    path = lambda name: os.path.join(folder, name)  # noqa: E731
    emulators = {
        "belt": Emulator(cli, ["ls5", "--port", path("ls5")], "belt"),
        "silo": Emulator(cli, ["uls", "--port", path("uls")], "silo"),
    }
    for emulator in emulators.values():
        emulator.start()
    with open(path("site.toml"), "w", encoding="utf-8") as f:
        f.write(f'[mqtt]\nbroker = "mqtt://127.0.0.1:{broker.port}"\n\n')
        f.write(f'[[sensor]]\nname = "belt"\nfamily = "ls5"\nport = "{path("ls5")}"\n\n')
        f.write(f'[[sensor]]\nname = "silo"\nfamily = "uls"\nport = "{path("uls")}"\n')
    service = Service(cli, path("site.toml"), folder)
    figures = {"folder": folder, "minutes": args.minutes, "samples": [], "outages": [], "broker_restarts": [],
               "downloads_ok": 0, "downloads_failed": 0, "sse_clients": 0, "sse_clients_failed": 0,
               "healthz_max_s": 0.0}
    failures = []
    try:
        wait_until(service.healthy, 30, "the service's /healthz")
        watcher = EventWatcher(service)
        status, _, body = service.request("POST", "/api/captures", {"sensors": []})
        capture = json.loads(body)["id"]
        start = time.monotonic()
        end = start + args.minutes * 60
        next_kill = start + args.kill_every
        next_broker = start + args.broker_every
        next_download = start + args.download_every
        next_sample = start
        churn_results, download_results = [], []
        churn_threads, victims = [], list(emulators)
        while time.monotonic() < end:
            now = time.monotonic()
            if now >= next_sample:
                asked = time.monotonic()
                healthy = service.healthy()
                took = time.monotonic() - asked
                figures["healthz_max_s"] = max(figures["healthz_max_s"], took)
                if not healthy:
                    failures.append(f"/healthz did not answer within 1 s at {now - start:.0f} s")
                entry = dict(service.process_figures(), at_s=round(now - start), mqtt_messages=subscriber.messages())
                figures["samples"].append(entry)
                print(json.dumps(entry), flush=True)
                next_sample += args.sample_every
            if now >= next_kill:
                name = victims[len(figures["outages"]) % len(victims)]
                killed_at = time.monotonic()
                emulators[name].kill()
                time.sleep(1.0)  # the outage itself: the sensor stays away a second
                emulators[name].start()
                figures["outages"].append({"sensor": name, "at_s": round(killed_at - start), "killed_at": killed_at})
                next_kill += args.kill_every
            if now >= next_broker:
                broker.stop()
                subscriber.stop()
                time.sleep(2.0)  # the broker stays away two seconds
                broker.start()
                subscriber.start()
                restarted = time.monotonic()
                try:
                    wait_until(lambda: subscriber.heard_since_start() > 0, 60, "MQTT messages after the broker restart")
                    back = time.monotonic() - restarted
                except RuntimeError:
                    back = None
                    failures.append(f"no MQTT message within 60 s of the broker restart at {now - start:.0f} s")
                figures["broker_restarts"].append({"at_s": round(now - start), "messages_again_after_s": back})
                next_broker += args.broker_every
            if now >= next_download:
                threading.Thread(target=download_all, args=(service, capture, download_results), daemon=True).start()
                next_download += args.download_every
            churn_threads = [t for t in churn_threads if t.is_alive()]
            if len(churn_threads) < 20:
                t = threading.Thread(target=churn_client, args=(service, random.uniform(1, 15), churn_results),
                                     daemon=True)
                t.start()
                churn_threads.append(t)
            time.sleep(0.5)  # the pace of the churn: a client every half second at most
        for t in churn_threads:
            t.join()
        time.sleep(5)  # the last outage's reconnect before the books close
        service.request("POST", f"/api/captures/{capture}/stop", {})
        info = json.loads(service.request("GET", f"/api/captures/{capture}")[2])
        _, _, sqlite_bytes = service.request("GET", f"/api/captures/{capture}/download?format=sqlite", timeout=300)
        with open(path("final.sqlite"), "wb") as f:
            f.write(sqlite_bytes)
        db = sqlite3.connect(path("final.sqlite"))
        integrity = db.execute("PRAGMA integrity_check").fetchone()[0]
        db.close()
        metrics = service.metrics()
        watcher.close()

        figures["downloads_ok"] = sum(download_results)
        figures["downloads_failed"] = len(download_results) - sum(download_results)
        figures["sse_clients"] = len(churn_results)
        figures["sse_clients_failed"] = len(churn_results) - sum(churn_results)
        figures["capture"] = {"samples": info.get("samples"), "events": info.get("events"), "lost": info.get("lost"),
                              "integrity_check": integrity}
        figures["metrics"] = {k: v for k, v in metrics.items()
                              if k.startswith(("rangekit_sensor_lost_total", "rangekit_sensor_records_total",
                                               "rangekit_sensor_disconnects_total",
                                               "rangekit_sensor_reconnects_total", "rangekit_http_streams_cut_off"))}
        for i, outage in enumerate(figures["outages"]):
            # The link events of this outage: up to the next outage of the same sensor.
            later = [o["killed_at"] for o in figures["outages"][i + 1:] if o["sensor"] == outage["sensor"]]
            kinds = watcher.between(outage["killed_at"], later[0] if later else None, outage["sensor"])
            outage["seen"] = kinds[:4]
            ok = "disconnected" in kinds and "reconnected" in kinds[kinds.index("disconnected"):] \
                if "disconnected" in kinds else False
            outage["disconnected_then_reconnected"] = ok
            if not ok:
                failures.append(f"outage of {outage['sensor']} at {outage['at_s']} s not seen as "
                                f"disconnected then reconnected: {kinds[:4]}")
        for outage in figures["outages"]:
            outage.pop("killed_at")
        lost = sum(v for k, v in metrics.items() if k.startswith("rangekit_sensor_lost_total"))
        if lost or info.get("lost"):
            failures.append(f"records lost: {lost} by the sensors' counters, {info.get('lost')} by the capture")
        if integrity != "ok":
            failures.append(f"capture integrity_check: {integrity}")
        if figures["downloads_failed"]:
            failures.append(f"{figures['downloads_failed']} downloads were not whole")
        # Flat means the typical value at the end is within 10 % of the typical value after the
        # warm-up: the medians of two windows, each as long as the warm-up. Single samples swing
        # with what runs at that moment (SSE clients and downloads hold sockets and buffers).
        after = [s for s in figures["samples"] if s["at_s"] >= args.warmup]
        window = max(1, int(args.warmup / args.sample_every))
        if len(after) >= 2 * window:
            early, late = after[:window], after[-window:]
            figures["flat"] = {}
            for key in ("rss_kb", "fds", "threads"):
                first, last = statistics.median(s[key] for s in early), statistics.median(s[key] for s in late)
                figures["flat"][key] = {"after_warmup_median": first, "end_median": last,
                                        "max": max(s[key] for s in after)}
                if key != "threads" and last > first * 1.10:
                    failures.append(f"{key}: median {last} over the last {args.warmup:.0f} s, over 10 % above "
                                    f"{first} after the warm-up")
        figures["failures"] = failures
    finally:
        stop(service.proc)
        for emulator in emulators.values():
            if emulator.proc and emulator.proc.poll() is None:
                stop(emulator.proc)
        subscriber.stop()
        broker.stop()
    summary = {k: v for k, v in figures.items() if k != "samples"}
    print(json.dumps(summary, indent=1))
    if args.report:
        with open(args.report, "w", encoding="utf-8") as f:
            json.dump(figures, f, indent=1)
    print("soak: " + ("all goals met" if not failures else f"{len(failures)} goal(s) missed"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
