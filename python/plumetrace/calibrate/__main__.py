import signal
import sys


def _interrupted(signum, frame):
    raise KeyboardInterrupt


# why: until main() takes the signals over, SIGTERM too ends the command with status 130
signal.signal(signal.SIGTERM, _interrupted)
try:
    from .cli import main

    status = main()
except KeyboardInterrupt:  # a signal before main() took the signals over
    status = 130
sys.exit(status)
