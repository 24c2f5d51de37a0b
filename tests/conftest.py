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
# workers, by default the files with the most tests first; a long file of few tests (the
# sanitizer run, about 10 minutes of CI's 2 cores, in 4 tests) then started half an hour into
# CI and ended minutes after the rest. pyproject.toml turns xdist's order off
# (--no-loadscope-reorder), and this hook gives its own: the files known to be long, then
# xdist's rule (most tests first) for the others. Longest first is the usual rule for such a
# schedule.
LONGEST_FIRST = ("tests/test83_the_core_runs_clean_under_asan_and_ubsan.py", "tests/blender/test_b23_gui_viewport.py",
                 "tests/test40_fuzz_and_sanitizers.py", "tests/test52_instruction_counts_run.py",
                 "tests/test51_speed_vs_error_runs.py", "tests/test50_benchmark_runs.py")


def pytest_collection_modifyitems(config, items):
    files = [item.nodeid.split("::")[0] for item in items]
    count = {f: files.count(f) for f in set(files)}
    rank = {path: i for i, path in enumerate(LONGEST_FIRST)}
    order = {f: (rank.get(f, len(rank)), -count[f]) for f in count}
    keyed = sorted(zip(items, files), key=lambda pair: order[pair[1]])      # (stable: a file's own order kept)
    items[:] = [item for item, _ in keyed]
