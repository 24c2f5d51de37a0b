"""The fuzzers run clean over the corpus on the release core, a short fixed budget for CI (issue 7).

* The NFF and PLY fuzzers (tests/fuzz, atheris) run over the checked-in
  corpus and must end cleanly: no uncaught exception other than
  SceneFileError / ValueError, no crash, no hang.
* The API fuzzer (fuzz_api.py, api_harness.py) does the same with programs of
  Scene, ray-query, RenderSettings and RenderJob calls with extreme values:
  only ValueError (RuntimeError for calls out of order) may escape.

Budgets: a fixed number of inputs per fuzzer (fuzzing.FUZZ_RUNS; about 15-20 s
each on a 2-core machine), capped at FUZZ_MAX_SECONDS; GRIDWALK_FUZZ_RUNS runs
longer by hand. The same fuzzers run on the ASan core in test83.

A crash the fuzzers find is written to the test's tmp directory and shown in
the failure message; add it under tests/fuzz/regressions/ (it then runs in
test41_fuzz_regressions.py).
"""
import pytest

from fuzzing import FUZZ_RUNS, run_fuzzer


@pytest.mark.parametrize("kind", ["nff", "ply", "api"])
def test_fuzzer_runs_clean_over_the_corpus(kind, tmp_path):
    run_fuzzer(kind, FUZZ_RUNS[kind], tmp_path)
