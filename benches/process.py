"""Timing one whole process, for the bench scripts beside this file."""

import os
import subprocess
import tempfile
import time


class Failed(Exception):
    """A timed process exited with an error; the message names the command and its
    standard error."""


def timed(command):
    """Wall seconds and CPU seconds (user + system) of one whole process. Raises
    `Failed` if it exits with an error."""
    start = time.perf_counter()
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    stderr = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        raise Failed(f"failed ({code}): {' '.join(map(str, command))}\n  {stderr.decode().strip()}")
    return wall, usage.ru_utime + usage.ru_stime


def measured(command):
    """Wall seconds, peak resident megabytes and standard output of one whole process.
    Raises `Failed` if it exits with an error."""
    with tempfile.TemporaryFile() as stderr:
        start = time.perf_counter()
        proc = subprocess.Popen([str(c) for c in command], stdout=subprocess.PIPE,
                                stderr=stderr)
        stdout = proc.stdout.read()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        code = os.waitstatus_to_exitcode(status)
        if code != 0:
            stderr.seek(0)
            raise Failed(f"failed ({code}): {' '.join(map(str, command))}\n  "
                         f"{stderr.read().decode(errors='replace').strip()[-2000:]}")
    return wall, usage.ru_maxrss / 1024, stdout.decode()
