"""The atheris entry point that fuzz_nff.py and fuzz_ply.py share: it fuzzes
one scene-file reader and, through it, the native core (see harness.py).

Each input is written to a temporary file with the reader's suffix and
loaded; SceneFileError is a clean refusal, a loaded file is built into a
gridwalk.Scene (ValueError is a clean refusal) and rendered at 8 x 8. Any
other exception, a crash or a sanitizer report is a finding: libFuzzer writes
the input to crash-<sha1> (see -artifact_prefix). libFuzzer adds the inputs it
finds to the first corpus directory, so give it a scratch directory first and
the checked-in corpus second. <format>.dict beside this file is used unless a
-dict= option is given.
"""
import sys
from pathlib import Path

import atheris

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
with atheris.instrument_imports(include=["gridwalk", "harness"]):
    import harness


def main(fmt: str):
    """Fuzz the reader of `fmt` ("nff" or "ply") with sys.argv's libFuzzer options."""
    argv = list(sys.argv)
    if not any(a.startswith("-dict=") for a in argv):
        argv.append(f"-dict={HERE / (fmt + '.dict')}")
    atheris.Setup(argv, lambda data: harness.run_bytes(data, "." + fmt))
    atheris.Fuzz()
