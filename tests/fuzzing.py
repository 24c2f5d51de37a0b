"""Shared by test40 (the fuzzers on the release core) and test83 (the core under ASan and
UBSan): budgets, running a fuzzer over the corpus, sanitizer logs. Not a test file."""
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FUZZ = ROOT / "tests" / "fuzz"
CORE_SRC = ROOT / "core"
PKG_SRC = ROOT / "core" / "python" / "gridwalk"
ASAN_BUILD = ROOT / "build" / "asan"
ASAN_PKG = ASAN_BUILD / "pkg"


def _runs(variable, default):
    value = os.environ.get(variable)
    return {kind: int(value) for kind in default} if value else default


# Inputs per fuzzer (the first runs are the fastest: the corpus is still small).
# Since the readers check each scene with the core as they load it (issue 16)
# an input costs about 1.4 times what it did, so the reader runs were cut from
# 100,000 (20,000 / 30,000 on the ASan core) to keep the run time, and on
# 2026-11-29 from 70,000 to 45,000 (the two took 183 s of CI's 27-minute run;
# GRIDWALK_FUZZ_RUNS runs longer by hand).
FUZZ_RUNS = _runs("GRIDWALK_FUZZ_RUNS", {"nff": 45000, "ply": 45000, "api": 8000})
ASAN_FUZZ_RUNS = _runs("GRIDWALK_ASAN_FUZZ_RUNS", {"nff": 15000, "ply": 20000, "api": 1500})
FUZZ_MAX_SECONDS = 90            # a cap per fuzzer run on a slow machine (inputs/s vary)
SANITIZER_MARKS = ("runtime error:", "AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer")

# Core test files run on the ASan build: the numbered hard-case and API tests,
# not this file (it would recurse) and not tests/blender.
# (test00 builds and runs the C++ unit tests, an uninstrumented binary of their own that the
# main run already runs: under ASan it only raced the main run's build of the same directory.)

def _require_atheris():
    try:
        import atheris  # noqa: F401
    except ImportError:
        pytest.fail("atheris is not installed: pip install '.[test]' (it is in the test extra)")


def _tail(text, n=6000):
    return text if len(text) <= n else "...\n" + text[-n:]


def with_logs(env, log_dir: Path):
    """`env` with ASan reports also written to log_dir/asan.<pid>: that catches
    them in child processes too (the CLI tests, test41), whatever those do with
    their stderr. GCC's UBSan ignores log_path and writes to stderr; its errors
    halt the process (halt_on_error=1)."""
    log_dir.mkdir(parents=True, exist_ok=True)
    return dict(env, ASAN_OPTIONS=f"{env['ASAN_OPTIONS']}:log_path={log_dir}/asan")


def sanitizer_reports(env):
    """Text of every ASan log written under `env` (see with_logs)."""
    dirs = [Path(opt.split("=", 1)[1]).parent for opt in env.get("ASAN_OPTIONS", "").split(":")
            if opt.startswith("log_path=")]
    return "".join(f"== {p.name}\n{p.read_text(errors='replace')}"
                   for d in dirs for p in sorted(d.glob("asan*")) if p.stat().st_size)


def run_fuzzer(kind, runs, workdir: Path, env=None):
    """Run tests/fuzz/fuzz_<kind>.py over the checked-in corpus; new inputs go
    to a scratch directory so the checked-in corpus is never modified. The
    seed is fixed (GRIDWALK_FUZZ_SEED, default 1) so that CI repeats one
    exploration; longer runs by hand use other seeds (docs/robustness.md)."""
    _require_atheris()
    workdir.mkdir(parents=True, exist_ok=True)
    new = workdir / "new"
    new.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, "-W", "ignore", str(FUZZ / f"fuzz_{kind}.py"),
           f"-atheris_runs={runs}", f"-max_total_time={FUZZ_MAX_SECONDS}", "-timeout=30",
           f"-seed={os.environ.get('GRIDWALK_FUZZ_SEED', '1')}",
           "-rss_limit_mb=4096", f"-artifact_prefix={workdir}/", "-print_final_stats=1",
           str(new), str(FUZZ / "corpus" / kind)]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(workdir),
                          timeout=FUZZ_MAX_SECONDS + 240)
    seconds = time.perf_counter() - t0
    output = proc.stdout + proc.stderr
    findings = sorted(p for p in workdir.iterdir()
                      if p.name.startswith(("crash-", "timeout-", "oom-", "leak-", "slow-unit-")))
    shown = "\n".join(f"{p.name}: {p.read_bytes()[:2000]!r}" for p in findings)
    logged = sanitizer_reports(env) if env else ""
    done = [line for line in output.splitlines() if re.match(r"Done \d+ (runs )?in \d+ second", line)]
    returncode = proc.returncode
    if returncode == -signal.SIGALRM and done and not findings:
        # Seen once in a 32 s run with -timeout=30: every input had run and
        # "Done" was printed, then the per-input timeout timer (SIGALRM every
        # timeout / 2 + 1 s, set by atheris) fired while the process was
        # exiting, presumably after its handler had been reset. A real timeout
        # reports "=== Timeout" and writes a timeout-* file instead.
        returncode = 0
    assert returncode == 0 and not findings and not logged, (
        f"fuzz_{kind} failed (exit {proc.returncode}); add each input below to "
        f"tests/fuzz/regressions/:\n{shown}\n{_tail(logged)}\n{_tail(output)}")
    assert not any(m in output for m in SANITIZER_MARKS), _tail(output)
    assert done, f"fuzz_{kind} exited without running its inputs:\n{_tail(output)}"
    print(f"fuzz_{kind}: {done[-1]} -> {seconds:.1f} s")
    return seconds
