#!/usr/bin/env python3
"""Atheris fuzzer for the NFF reader and, through it, the native core.

    python tests/fuzz/fuzz_nff.py -atheris_runs=3000 NEW_DIR tests/fuzz/corpus/nff

See reader_fuzzer.py for what each input goes through and what counts as a finding.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import reader_fuzzer  # noqa: E402

if __name__ == "__main__":
    reader_fuzzer.main("nff")
