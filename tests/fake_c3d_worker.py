"""A stand-in for core.markers.c3d_worker that misbehaves on purpose (tests/test_markers_c3d.py):
``python -m tests.fake_c3d_worker FILE LIMIT`` segfaults if FILE ends in ``segv.c3d``, hangs if it
ends in ``hang.c3d``, and otherwise exits with status 7 after a message on stderr."""

import os
import signal
import sys
import time

if __name__ == "__main__":
    name = sys.argv[1]
    if name.endswith("segv.c3d"):
        os.kill(os.getpid(), signal.SIGSEGV)
    if name.endswith("hang.c3d"):
        time.sleep(600)
    print("something odd happened", file=sys.stderr)
    sys.exit(7)
