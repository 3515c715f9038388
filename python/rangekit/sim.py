"""The emulators, for your own tests: ``with rangekit.sim.<family>() as unit: ...``, one
function for each family of :func:`rangekit.families`.

Each emulator is the ``rangekit sim <family>`` command of the CLI run as a child process
(the same firmware model the CLI's tests use), on pseudo-terminals in a fresh temporary
directory: ``unit.port`` is the path to open, ``unit.control`` the path of its JSON-lines
control socket and ``unit.command({...})`` sends one command there
(docs/emulator-<family>.md). ``unit.kill()`` ends it as a cable pulled out; ``unit.restart()``
brings it back on the same paths, so a driver's stream reconnects.

The CLI is found as ``$RANGEKIT_CLI``, else beside the build tree's module, else
``rangekit`` on ``PATH`` (``/usr/bin/rangekit`` of the .deb).
"""

from __future__ import annotations

import importlib
import json
import os
import shutil
import socket
import subprocess
import tempfile
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

from ._families import FAMILIES
from .errors import LinkError

__all__ = ["Emulator", "cli_path", *FAMILIES]

PathLike = Union[str, "os.PathLike[str]"]


def cli_path() -> str:
    """The ``rangekit`` executable the emulators run."""
    configured = os.environ.get("RANGEKIT_CLI")
    if configured:
        return configured
    try:
        from . import _build_paths  # only in the build tree

        if os.path.exists(_build_paths.CLI):
            return _build_paths.CLI
    except ImportError:
        pass
    found = shutil.which("rangekit")
    if found:
        return found
    raise LinkError("the rangekit CLI was not found: set RANGEKIT_CLI or put rangekit on PATH", "io")


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string: the same escapes
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(item) for item in value) + "]"
    raise TypeError(f"a scene value must be a bool, number, string or list, not {type(value).__name__}")


def toml_text(scene: Mapping[str, Any]) -> str:
    """A scene dict as the TOML file ``rangekit sim --scene`` reads: tables for dicts,
    arrays of tables for lists of dicts (``{"target": {"position_mm": 28.0}}``)."""
    lines: List[str] = []
    for key, value in scene.items():
        if not isinstance(value, Mapping) and not (isinstance(value, list) and value and isinstance(value[0], Mapping)):
            lines.append(f"{key} = {_toml_value(value)}")
    for key, value in scene.items():
        if isinstance(value, Mapping):
            lines.append(f"[{key}]")
            lines += [f"{name} = {_toml_value(item)}" for name, item in value.items()]
        elif isinstance(value, list) and value and isinstance(value[0], Mapping):
            for table in value:
                lines.append(f"[[{key}]]")
                lines += [f"{name} = {_toml_value(item)}" for name, item in table.items()]
    return "\n".join(lines) + "\n"


class Emulator:
    """One emulated sensor in a child process; a context manager that stops it and removes its files."""

    def __init__(self, family: str, scene: Optional[Union[PathLike, Mapping[str, Any]]] = None,
                 arguments: Sequence[str] = ()):
        if family not in FAMILIES:
            raise ValueError("family must be " + " or ".join(repr(name) for name in FAMILIES))
        self.family = family
        self._directory = tempfile.mkdtemp(prefix=f"rangekit-sim-{family}-")
        #: The serial port path to open (the sensor's measuring line).
        self.port = os.path.join(self._directory, family)
        # A family whose emulator has a configuration port too names its file in its module.
        config_name = getattr(importlib.import_module(f".{family}", __package__), "_SIM_CONFIG_PORT", None)
        #: The configuration port, for a family that has one (``--config-port``); else None.
        self.config_port: Optional[str] = os.path.join(self._directory, config_name) if config_name else None
        #: The control socket's path (JSON lines).
        self.control = os.path.join(self._directory, "control")
        self._scene = scene
        self._arguments = list(arguments)
        self._process: Optional[subprocess.Popen] = None
        self.log_path = os.path.join(self._directory, "sim.log")

    def argv(self) -> List[str]:
        argv = [cli_path(), "sim", self.family, "--port", self.port, "--control", self.control]
        if self.config_port:
            argv += ["--config-port", self.config_port]
        if isinstance(self._scene, Mapping):
            scene_path = os.path.join(self._directory, "scene.toml")
            with open(scene_path, "w") as scene_file:
                scene_file.write(toml_text(self._scene))
            argv += ["--scene", scene_path]
        elif self._scene is not None:
            argv += ["--scene", os.fspath(self._scene)]
        return argv + self._arguments

    def start(self) -> "Emulator":
        """Starts the child and waits for its ready line (no sleeping)."""
        if self._process is not None:
            return self
        with open(self.log_path, "ab") as log:
            self._process = subprocess.Popen(self.argv(), stdout=subprocess.PIPE, stderr=log, stdin=subprocess.DEVNULL)
        assert self._process.stdout is not None
        ready = self._process.stdout.readline().decode(errors="replace")
        if "ready:" not in ready:
            self.kill()
            with open(self.log_path, errors="replace") as log:
                raise LinkError(f"rangekit sim {self.family} did not start: {log.read().strip()}", "io")
        return self

    def command(self, command: Mapping[str, Any]) -> Dict[str, Any]:
        """Sends one control command (``{"cmd": "outputs"}``) and returns the reply."""
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as connection:
            connection.connect(self.control)
            connection.sendall((json.dumps(dict(command)) + "\n").encode())
            reply = b""
            while not reply.endswith(b"\n"):
                chunk = connection.recv(65536)
                if not chunk:
                    break
                reply += chunk
        return json.loads(reply.decode()) if reply.strip() else {}

    @property
    def running(self) -> bool:
        return self._process is not None and self._process.poll() is None

    def kill(self) -> None:
        """Ends the emulator (SIGTERM, waited for): its ptys and their paths vanish, as a cable pulled."""
        process, self._process = self._process, None
        if process is None:
            return
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        if process.stdout:
            process.stdout.close()

    def restart(self) -> "Emulator":
        """Starts it again on the same paths (a driver's stream reconnects)."""
        self.kill()
        return self.start()

    def close(self) -> None:
        self.kill()
        shutil.rmtree(self._directory, ignore_errors=True)

    def __enter__(self) -> "Emulator":
        return self.start()

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<rangekit.sim.Emulator {self.family} on {self.port}>"


def _starter(family: str) -> Callable[..., Emulator]:
    def start(scene: Optional[Union[PathLike, Mapping[str, Any]]] = None, arguments: Sequence[str] = ()) -> Emulator:
        return Emulator(family, scene, arguments)

    start.__name__ = start.__qualname__ = family
    start.__doc__ = (
        f"An emulator of the family {family!r}: ``scene`` is a TOML file (docs/emulator-{family}.md) or a "
        f"dict of its tables; ``arguments`` are more ``rangekit sim {family}`` options."
    )
    return start


# rangekit.sim.<family>(scene, arguments), one for each family.
for _family in FAMILIES:
    globals()[_family] = _starter(_family)
