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

# The longest files start first. pytest-xdist (--dist=loadfile) hands whole files to its
# workers in collection order, so a long file collected late (the sanitizer run, about 8
# minutes of CI's 2 cores, sorts after the Blender tests and most others) was the last to
# finish, minutes after the rest. Longest first is the usual rule for such a schedule.
LONGEST_FIRST = ("tests/test40_fuzz_and_sanitizers.py", "tests/blender/test_b23_gui_viewport.py",
                 "tests/test52_instruction_counts_run.py", "tests/test51_speed_vs_error_runs.py",
                 "tests/test50_benchmark_runs.py")


def pytest_collection_modifyitems(config, items):
    rank = {path: i for i, path in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))
