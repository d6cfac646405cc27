"""A sweep's one-line progress report on a terminal."""

import sys
import threading
import time as clock


class Progress:
    """Runs done, running, failed and time left, on one line of stderr
    when it is a terminal (nothing otherwise)."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled = total, enabled and sys.stderr.isatty()
        self.done = self.failed = self.running = 0
        self.start = clock.perf_counter()
        self.lock = threading.Lock()

    def update(self, done: int = 0, failed: int = 0, running: int = 0) -> None:
        """Count ``done`` more runs ended, ``failed`` of them not ``ok``,
        and ``running`` more (or fewer) under way."""
        with self.lock:
            self.done += done
            self.failed += failed
            self.running += running
            if not self.enabled:
                return
            elapsed = clock.perf_counter() - self.start
            left = (elapsed / self.done * (self.total - self.done)) if self.done else float("nan")
            sys.stderr.write(f"\r{self.done}/{self.total} runs done, {self.running} running, "
                             f"{self.failed} failed, {left:.0f} s left   ")
            sys.stderr.flush()

    def close(self) -> None:
        """End the line."""
        if self.enabled:
            sys.stderr.write("\n")
