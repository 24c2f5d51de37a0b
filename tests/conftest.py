"""Suite-wide setup: the Ctrl-C that tests send reaches the processes they start.

A shell without job control (a CI script, a runner) starts background jobs
(`cmd &`) with SIGINT ignored, and an ignored signal stays ignored across
fork and exec: the CLI, Blender and the farm's workers that the tests start
would never see the Ctrl-C the tests send them (test13, b11 and b30 failed
so). A handler, unlike an ignored signal, is reset to the default on exec, so
with Python's own handler back in place here every child starts with Ctrl-C
live, as it does from a terminal."""
import signal

if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
