#!/usr/bin/env python3
"""tidy.py BUILD JOBS: clang-tidy over every file of src/, in parallel, with the compile
database of BUILD (an existing build: `make test`'s). Prints "clang-tidy: clean", or each
warning and exits 1.

The database is BUILD's own, less the precompiled-header flags (g++'s -include of
cmake_pch.hxx would make clang parse every heavy header again, and its .gch is g++'s
format): BUILD/tidy/compile_commands.json.

A file found clean is remembered under ~/.cache/rangekit-tidy by a hash of what the
check depends on: clang-tidy's version, .clang-tidy, the file's flags and its preprocessed
text (every header it includes). An unchanged file is not checked again. CCACHE_DISABLE=1
or RANGEKIT_TIDY_CACHE=0 checks every file (what a cold run measures)."""
import concurrent.futures
import hashlib
import json
import os
import re
import shlex
import subprocess
import sys

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CACHE = os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "rangekit-tidy")


def tidy_database(build):
    with open(os.path.join(build, "compile_commands.json"), encoding="utf-8") as f:
        entries = json.load(f)
    kept = []
    seen = set()
    for entry in entries:
        # A file two targets compile (the CLI's sim_process.cpp, in the benchmarks too) is checked once.
        if not entry["file"].startswith(os.path.join(SOURCE, "src") + os.sep) or entry["file"] in seen:
            continue
        seen.add(entry["file"])
        words = shlex.split(entry["command"]) if "command" in entry else entry["arguments"]
        arguments = []
        i = 0
        while i < len(words):
            if words[i] == "-include" and i + 1 < len(words) and "cmake_pch" in words[i + 1]:
                i += 2
                continue
            if words[i] != "-Winvalid-pch":
                arguments.append(words[i])
            i += 1
        kept.append({"directory": entry["directory"], "file": entry["file"], "arguments": arguments})
    if not kept:
        sys.exit(f"tidy: {build}/compile_commands.json lists no file under {SOURCE}/src (configure {build} first)")
    os.makedirs(os.path.join(build, "tidy"), exist_ok=True)
    with open(os.path.join(build, "tidy", "compile_commands.json"), "w", encoding="utf-8") as f:
        json.dump(kept, f, indent=1)
    return kept


def cache_key(entry, salt):
    # The preprocessed text: the same compiler and flags, -E instead of -c/-o.
    arguments = []
    skip = False
    for word in entry["arguments"]:
        if skip:
            skip = False
        elif word == "-o":
            skip = True
        elif word != "-c":
            arguments.append(word)
    text = subprocess.run(arguments + ["-E", "-P"], cwd=entry["directory"], capture_output=True, check=True).stdout
    digest = hashlib.sha256(salt)
    digest.update(" ".join(arguments).replace(SOURCE, ".").encode())
    digest.update(text.replace(SOURCE.encode(), b"."))
    return digest.hexdigest()


def run_tidy(database, file):
    """clang-tidy on one file: its output, exit status and the CPU seconds it used (user +
    system, so that a run beside other work still says what each file costs)."""
    child = subprocess.Popen(["clang-tidy", "-p", database, "--quiet", file], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    output = child.stdout.read()
    child.stdout.close()
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait again
    return output, child.returncode, usage.ru_utime + usage.ru_stime


def main():
    build, jobs = sys.argv[1], int(sys.argv[2])
    entries = tidy_database(build)
    use_cache = os.environ.get("CCACHE_DISABLE", "") in ("", "0") and os.environ.get("RANGEKIT_TIDY_CACHE") != "0"
    version = subprocess.run(["clang-tidy", "--version"], capture_output=True, check=True).stdout
    with open(os.path.join(SOURCE, ".clang-tidy"), "rb") as f:
        salt = version + f.read()
    database = os.path.join(build, "tidy")
    seconds = {}

    def check(entry):
        key = cache_key(entry, salt) if use_cache else None
        if key and os.path.exists(os.path.join(CACHE, key)):
            return "", "unchanged"
        output, returncode, cpu = run_tidy(database, entry["file"])
        seconds[entry["file"]] = cpu
        findings = "\n".join(line for line in output.splitlines() if re.search(r"(warning|error):", line))
        clean = returncode == 0 and not findings
        if clean and key:
            os.makedirs(CACHE, exist_ok=True)
            open(os.path.join(CACHE, key), "w").close()
        return (findings or output), ("clean" if clean else "failed")

    failed, unchanged = [], 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for output, state in pool.map(check, entries):
            if state == "failed":
                failed.append(output)
            unchanged += state == "unchanged"
    if failed:
        print("\n".join(sorted(set("\n".join(failed).splitlines()))))
        sys.exit(1)
    print(f"clang-tidy: clean ({len(entries)} files of src/, {unchanged} unchanged since a clean check)")
    if seconds:
        slowest = sorted(seconds.items(), key=lambda item: -item[1])
        print(f"clang-tidy: {sum(seconds.values()):.0f} s of CPU for {len(seconds)} files; the slowest:")
        for file, cpu in slowest[:10]:
            print(f"  {cpu:6.1f} s  {os.path.relpath(file, SOURCE)}")


if __name__ == "__main__":
    main()
