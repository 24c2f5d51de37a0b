#!/usr/bin/env python3
"""Atheris fuzzer for the PLY reader and, through it, the native core.

    python tests/fuzz/fuzz_ply.py -atheris_runs=3000 NEW_DIR tests/fuzz/corpus/ply

Each input is written to a temporary .ply file and loaded; SceneFileError is
a clean refusal, a loaded file is built into a gridwalk.Scene (ValueError is
a clean refusal) and rendered at 8 x 8 (see harness.py). Any other exception,
a crash or a sanitizer report is a finding: libFuzzer writes the input to
crash-<sha1> (see -artifact_prefix). libFuzzer adds the inputs it finds to the
first corpus directory, so give it a scratch directory first and the
checked-in corpus second. ply.dict is used unless a -dict= option is given.
"""
import sys
from pathlib import Path

import atheris

sys.path.insert(0, str(Path(__file__).resolve().parent))
with atheris.instrument_imports(include=["gridwalk", "harness"]):
    import harness


def TestOneInput(data: bytes):
    harness.run_bytes(data, ".ply")


def main():
    argv = list(sys.argv)
    if not any(a.startswith("-dict=") for a in argv):
        argv.append(f"-dict={Path(__file__).resolve().parent / 'ply.dict'}")
    atheris.Setup(argv, TestOneInput)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
