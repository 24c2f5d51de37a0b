#!/usr/bin/env python3
"""Atheris fuzzer for the public API and, through it, the native core: each
input is a short program of Scene, ray-query, RenderSettings and RenderJob
calls with extreme values (see api_harness.py).

    python tests/fuzz/fuzz_api.py -atheris_runs=3000 NEW_DIR tests/fuzz/corpus/api
"""
import sys
from pathlib import Path

import atheris

sys.path.insert(0, str(Path(__file__).resolve().parent))
with atheris.instrument_imports(include=["gridwalk", "api_harness"]):
    import api_harness


def TestOneInput(data: bytes):
    api_harness.run_bytes(data)


def main():
    atheris.Setup(list(sys.argv), TestOneInput)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
