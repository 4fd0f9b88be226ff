"""Ctrl-C stops a long call within about a second: SIGINT to a process one
second into truth (about 12 s here alone) or a compression of 2,000 runs
(about 20 s) raises KeyboardInterrupt there, and the next call runs."""

import signal
import subprocess
import sys
import textwrap
import time

import pytest

CALLS = {
    "truth": "rgc.truth(rgc.generate(rgc.Box(10.0), density=44, gamma=23, seed=1))",
    "compress": "rgc.compress(rgc.generate(rgc.Box(5.0), density=40, gamma=23, seed=1), runs=2000)",
}


@pytest.mark.parametrize("name", list(CALLS))
def test_ctrl_c_stops_a_long_call_within_a_second(name):
    script = textwrap.dedent(
        f"""
        import signal
        import time
        import rgc
        # A child of a shell's background job inherits SIGINT ignored, and
        # Python then installs no handler: restore the terminal's default.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        small = rgc.generate(rgc.Box(4.0), density=40, gamma=23, seed=1)
        rgc.truth(small)
        print("started", flush=True)
        start = time.monotonic()
        try:
            {CALLS[name]}
            print("finished", time.monotonic() - start, flush=True)
        except KeyboardInterrupt:
            print("interrupted", time.monotonic() - start, flush=True)
        # The abandoned work keeps its own threads: the next call is not held up.
        start = time.monotonic()
        rgc.truth(small)
        print("next", time.monotonic() - start, flush=True)
        """
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == "started\n"
        time.sleep(1.0)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        what, seconds = child.stdout.readline().split()
        stopped = time.monotonic() - sent
        assert what == "interrupted", f"the call ran to its end ({seconds} s) before Ctrl-C took"
        assert stopped < 1.0, f"KeyboardInterrupt came {stopped:.2f} s after SIGINT"
        next_call, next_seconds = child.stdout.readline().split()
        assert next_call == "next" and float(next_seconds) < 5.0, next_seconds
        assert child.wait(timeout=30) == 0, child.stderr.read()
    finally:
        child.kill()
        child.wait()
