"""Processes that keep a core busy, as a robot's other CPU-bound work does (a planner, a second driver):
started and stopped by the benchmark itself, so every run is measured against the same load."""
import contextlib
import subprocess
import sys


@contextlib.contextmanager
def busy_processes(count):
    """`count` processes spinning at full CPU for the duration of the `with` block."""
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]
    try:
        yield burners
    finally:
        for burner in burners:
            burner.kill()
            burner.wait()
