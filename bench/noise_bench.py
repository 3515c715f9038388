#!/usr/bin/python3
"""Noise benchmark (docs/reliability.md): how many printed values were wrong under line noise,
and how many of those were flagged suspect.

For each family (ULS, LS5) and each condition (clean; bit-error rate 1e-4; 1e-3; byte drop
and duplicate 1e-3) it starts the emulator on a moving target with the line fault injection
of its control socket (`noise`), streams with `rangekit <family> stream --format jsonl`,
and compares every printed value with what the emulator sent before the noise
(`sim --wire-log`): a printed value is right when it equals the next value sent (or one of
the few after it, when lines were lost on the way), wrong otherwise.

    /usr/bin/python3 bench/noise_bench.py [--build build] [--seconds 60] [--family uls|ls5|both] [--top-speed]
                                          [--still]

With --still the target stands still (ULS at 50 m, LS5 100/200 at 200 mm, code 25000), and each
printed distance is also judged against the truth: of the values further from it than the
document's stated accuracy (ULS §9 ±4 cm; LS5 table 3.1 ±0.15 % of the range, 75 codes), and of
those further than ten times it, how many were flagged.

Only the Python standard library; needs the built CLI (build/rangekit).
"""

import argparse
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time

CONDITIONS = [
    ("clean", {}),
    ("bit errors 1e-4", {"bit_error_rate": 1e-4}),
    ("bit errors 1e-3", {"bit_error_rate": 1e-3}),
    ("drop + duplicate 1e-3", {"drop_rate": 1e-3, "duplicate_rate": 1e-3}),
]
SCENE_TOP_SPEED = {"uls": 2.0, "ls5": 0.016}  # m/s, from the scenes below
LOOKAHEAD = 8  # lines a printed value may skip (lost on the way) and still count as right
RESYNC = 20000  # how far ahead a run of three printed values is looked for after a miss

# ULS: a target going 20 m -> 80 m -> 20 m in 60 s: 2 m/s, the scene's top speed.
ULS_SCENE = """
[[targets]]
name = "crane"
reflectivity = 0.9
path = [[0, 20.0], [30, 80.0], [60, 20.0]]
repeat = true
"""
# LS5 100/200 (range 200 mm from 100 mm): 120 -> 280 -> 120 mm in 20 s, 16 mm/s.
LS5_SCENE = """
[target]
path = [[0.0, 120.0], [10.0, 280.0], [20.0, 120.0]]
repeat = true
reflectivity = 0.8
"""


# Still targets, their true readings (ULS mm, LS5 code) and the stated accuracy in those units.
ULS_STILL_SCENE = """
[[targets]]
name = "wall"
reflectivity = 0.9
distance_m = 50.0
"""
LS5_STILL_SCENE = """
[target]
position_mm = 200.0
reflectivity = 0.8
"""
STILL_TRUTH = {"uls": 50000, "ls5": 25000}
ACCURACY = {"uls": 40, "ls5": 75}


def control(path, request):
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.settimeout(10)
        sock.connect(path)
        sock.sendall((json.dumps(request) + "\n").encode())
        reply = b""
        while not reply.endswith(b"\n"):
            chunk = sock.recv(4096)
            if not chunk:
                break
            reply += chunk
    answer = json.loads(reply)
    if "error" in answer:
        raise RuntimeError(f"control {request}: {answer['error']}")
    return answer


def start_emulator(cli, family, work, seed, still):
    scene = os.path.join(work, "scene.toml")
    with open(scene, "w") as f:
        if still:
            f.write(ULS_STILL_SCENE if family == "uls" else LS5_STILL_SCENE)
        else:
            f.write(ULS_SCENE if family == "uls" else LS5_SCENE)
    port = os.path.join(work, family)
    ctl = os.path.join(work, "control")
    wire = os.path.join(work, "wire.bin")
    if family == "uls":
        # Factory MO 0: measurements leave on the configuration port, the one streamed here.
        args = [cli, "sim", "uls", "--config-port", port, "--port", port + "-universal"]
    else:
        args = [cli, "sim", "ls5", "--port", port, "--model", "100/200"]
    args += ["--control", ctl, "--scene", scene, "--seed", str(seed), "--wire-log", wire]
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    if "ready" not in line:
        proc.kill()
        raise RuntimeError(f"{family} emulator did not start: {line}{proc.stderr.read()}")
    return proc, port, ctl, wire


def truth_values(family, wire):
    with open(wire, "rb") as f:
        data = f.read().decode("latin-1")
    if family == "uls":
        return [(int(m.group(1).replace(".", "")), int(m.group(2)))
                for m in re.finditer(r"\$BM,(-?\d+\.\d{3}),(\d+)\r", data)]
    return [int(m.group(1)) for m in re.finditer(r"!(\d{5})\r", data)]


def printed_values(family, out):
    values, events = [], {}
    with open(out) as f:
        for line in f:
            item = json.loads(line)
            if "event" in item:
                events[item["event"]] = events.get(item["event"], 0) + 1
                continue
            suspect = bool(item.get("suspect"))
            if family == "uls":
                if item["kind"] != "averaging" or item["distance_m"] is None:
                    continue
                width = item["pulse_width_ns"]  # 3 decimals: back to the wire's integer ps
                value = (round(item["distance_m"] * 1000), None if width is None else round(width * 1000))
            else:
                if item["kind"] != "result" or item["code"] is None or item["code"] > 50000:
                    continue
                value = item["code"]
            values.append((value, suspect, item.get("suspect_reason", "")))
    return values, events


def find_run(truth, run, start, end):
    """Where `run` (three values) appears in a row in truth[start:end], or None."""
    if len(run) < 3:
        return None
    for j in range(start, min(end, len(truth) - 2)):
        if truth[j] == run[0] and truth[j + 1] == run[1] and truth[j + 2] == run[2]:
            return j
    return None


def judge_against_truth(family, printed, result):
    """Still target: printed distances further from the truth than the accuracy (and ten times it)."""
    truth, accuracy = STILL_TRUTH[family], ACCURACY[family]
    for key in ("over_accuracy", "over_accuracy_flagged", "over_ten", "over_ten_flagged"):
        result[key] = 0
    for value, suspect, reason in printed:
        distance = value[0] if isinstance(value, tuple) else value
        error = abs(distance - truth)
        if error > accuracy:
            result["over_accuracy"] += 1
            result["over_accuracy_flagged"] += 1 if suspect else 0
            if not suspect:
                result.setdefault("missed_errors", []).append(error)
            if not suspect and len(result["examples"]) < 9:
                result["examples"].append(f"unflagged {distance} ({error} from the truth {truth})")
        if error > 10 * accuracy:
            result["over_ten"] += 1
            result["over_ten_flagged"] += 1 if suspect else 0


def compare(truth, printed):
    """Counts right/wrong printed values against the sent sequence."""
    # Anchor: the first three printed values found in a row in what was sent.
    position = None
    for start in range(len(printed) - 2):
        triple = [v for v, _, _ in printed[start:start + 3]]
        for j in range(len(truth) - 2):
            if truth[j:j + 3] == triple:
                position = j
                break
        if position is not None:
            printed = printed[start:]
            break
    if position is None:
        raise RuntimeError("no three printed values in a row match what the emulator sent")
    result = {"printed": 0, "wrong": 0, "wrong_flagged": 0, "right_flagged": 0, "resyncs": 0, "examples": []}
    values = [v for v, _, _ in printed]
    for i, (value, suspect, reason) in enumerate(printed):
        result["printed"] += 1
        following = values[i + 1] if i + 1 < len(values) else None
        at = lambda k: truth[position + k] if position + k < len(truth) else None  # noqa: E731
        right = False
        if value == at(0):
            right, position = True, position + 1
        elif following is not None and following == at(1):
            position += 1  # the lines go on in place: this one is truth[position], corrupted
        else:
            # Lines lost on the way: the value further on, with the next one after it.
            for k in range(1, LOOKAHEAD):
                if value == at(k) and (following is None or following in truth[position + k + 1:position + k + 3]):
                    right, position = True, position + k + 1
                    break
            if not right:
                # More lines lost than LOOKAHEAD (a full queue, a long burst): this value and
                # the next two in a row further on (or just behind) mean the values are right again.
                found = find_run(truth, values[i:i + 3], max(0, position - LOOKAHEAD), position + RESYNC)
                if found is not None:
                    right, position = True, found + 1
                    result["resyncs"] += 1
                else:
                    position += 1  # it stood for one line sent
        if right:
            if suspect:
                result["right_flagged"] += 1
                if len(result["examples"]) < 3:
                    result["examples"].append(f"false flag {value}: {reason}")
        else:
            result["wrong"] += 1
            result["wrong_flagged"] += 1 if suspect else 0
            sent = truth[position - 1] if 0 < position <= len(truth) else None
            if isinstance(value, tuple) and isinstance(sent, tuple):
                # ULS: which field was wrong, taking the line it stood for as the one sent.
                for index, field in ((0, "distance"), (1, "pulse_width")):
                    if value[index] != sent[index]:
                        result[f"wrong_{field}"] = result.get(f"wrong_{field}", 0) + 1
                        result[f"wrong_{field}_flagged"] = result.get(f"wrong_{field}_flagged", 0) + (
                            1 if suspect else 0)
            if not suspect and len(result["examples"]) < 6:
                result["examples"].append(f"unflagged {value} (sent {sent})")
    return result


def run_one(cli, family, name, noise, seconds, seed, max_speed, still):
    with tempfile.TemporaryDirectory(prefix="noise-bench-") as work:
        proc, port, ctl, wire = start_emulator(cli, family, work, seed, still)
        try:
            if family == "uls":
                # 100 measurements a second (PRF 2000 / PPM 20), range and pulse width (DM 2).
                subprocess.run([cli, "uls", "set", "--port", port, "averaging-weight=16", "ppm=20",
                                "prf-hz=2000"], check=True, capture_output=True, text=True)
            else:
                # 1000 records a second, the LS5's fastest stream (§8.4: t = 1 ms, n = 1).
                subprocess.run([cli, "ls5", "set", "--port", port, "period-ms=1"], check=True, capture_output=True,
                               text=True)
            if noise:
                line = "configuration" if family == "uls" else None
                request = {"cmd": "noise", **noise}
                if line:
                    request["line"] = line
                control(ctl, request)
            out = os.path.join(work, "out.jsonl")
            speed = [] if max_speed is None else ["--max-speed", str(max_speed[family])]
            stream = subprocess.run([cli, family, "stream", "--port", port, "--format", "jsonl", "--quiet",
                                     "--duration", str(seconds), "--out", out] + speed,
                                    capture_output=True, text=True)
            if stream.returncode not in (0,):
                raise RuntimeError(f"{family} stream exited {stream.returncode}: {stream.stderr[-400:]}")
        finally:
            proc.send_signal(signal.SIGTERM)
            proc.wait(timeout=30)
        truth = truth_values(family, wire)
        printed, events = printed_values(family, out)
        result = compare(truth, printed)
        if still:
            judge_against_truth(family, printed, result)
        result["bad_frames"] = events.get("bad_frame", 0)
        return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--seconds", type=float, default=60)
    parser.add_argument("--family", choices=["uls", "ls5", "both"], default="both")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--top-speed", action="store_true",
                        help="stream with --max-speed at the scenes' top speeds (ULS 2 m/s, LS5 0.016 m/s) "
                             "instead of the defaults")
    parser.add_argument("--still", action="store_true",
                        help="a still target, each value also judged against the truth and the stated accuracy")
    args = parser.parse_args()
    max_speed = SCENE_TOP_SPEED if args.top_speed else None
    cli = os.path.abspath(os.path.join(args.build, "rangekit"))
    families = ["uls", "ls5"] if args.family == "both" else [args.family]
    print(f"noise bench: {args.seconds:g} s per run, seed {args.seed}, "
          + ("a still target, " if args.still else "a moving target, ") + "max_speed "
          + ("the scenes' top speeds " + str(SCENE_TOP_SPEED) if max_speed else "the defaults"))
    print(f"{'family':6} {'condition':24} {'printed':>8} {'wrong':>6} {'flagged':>8} {'share':>7} "
          f"{'false flags':>11} {'bad frames':>10}")
    failed = False
    for family in families:
        for name, noise in CONDITIONS:
            started = time.monotonic()
            try:
                r = run_one(cli, family, name, noise, args.seconds, args.seed, max_speed, args.still)
            except (RuntimeError, subprocess.SubprocessError, OSError) as error:
                print(f"{family:6} {name:24} failed: {error}")
                failed = True
                continue
            share = f"{100.0 * r['wrong_flagged'] / r['wrong']:.1f}%" if r["wrong"] else "-"
            right = r["printed"] - r["wrong"]
            false_share = f"{r['right_flagged']} ({100.0 * r['right_flagged'] / right:.3f}%)" if right else "-"
            print(f"{family:6} {name:24} {r['printed']:8} {r['wrong']:6} {r['wrong_flagged']:8} {share:>7} "
                  f"{false_share:>11} {r['bad_frames']:10}   [{time.monotonic() - started:.0f} s]")
            for field in ("distance", "pulse_width"):
                if r.get(f"wrong_{field}"):
                    print(f"       of which {field} wrong: {r[f'wrong_{field}']}, "
                          f"flagged {r[f'wrong_{field}_flagged']}")
            if "over_accuracy" in r:
                def share_of(flagged, total):
                    return f"{flagged} of {total} ({100.0 * flagged / total:.1f}%)" if total else "none"
                print(f"       beyond the accuracy ({ACCURACY[family]}): flagged "
                      f"{share_of(r['over_accuracy_flagged'], r['over_accuracy'])}; beyond ten times it: "
                      f"{share_of(r['over_ten_flagged'], r['over_ten'])}")
                if r.get("missed_errors"):
                    print(f"       missed, their errors: {sorted(r['missed_errors'])}")
            if r["resyncs"]:
                print(f"       {r['resyncs']} resynchronisations (more than {LOOKAHEAD} lines lost at once)")
            for example in r["examples"]:
                print(f"       {example}")
            sys.stdout.flush()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
