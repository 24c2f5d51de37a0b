"""The build falls back to no link-time optimisation when the compiler cannot
link with -flto (core/CMakeLists.txt, CheckIPOSupported).

A GCC whose LTO plugin is broken configures fine and then fails at the final
link with "could not run lto-wrapper" (the device machine's /opt/gcc did).
Here a wrapper around the system g++ fails every -flto link the same way: the
configure must say so and leave -flto out of the module's build; with the
plain compiler it must keep LTO on (the g++ on PATH, which builds the
project in CI: a machine whose g++ itself cannot link with -flto fails that
second test, rightly, since its wheel is then built without LTO). Configure
only (a few seconds): the wrapper's full build was checked by hand (it
links, without LTO).
"""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BROKEN_LTO_GXX = """#!/bin/sh
lto=0; compile=0
for a in "$@"; do case "$a" in -flto*) lto=1;; -c) compile=1;; esac; done
if [ $lto = 1 ] && [ $compile = 0 ]; then
  echo "lto-wrapper: fatal error: could not run lto-wrapper" >&2; exit 1
fi
exec "{gxx}" "$@"
"""


def configure(build: Path, *extra):
    tools = Path(sys.executable).parent
    env = dict(os.environ, PATH=f"{tools}{os.pathsep}{os.environ.get('PATH', '')}")
    proc = subprocess.run([str(tools / "cmake"), "-S", str(ROOT / "core"), "-B", str(build), "-G", "Ninja",
                           "-DCMAKE_BUILD_TYPE=Release", f"-DPython_EXECUTABLE={sys.executable}", *extra],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    return proc.stdout + proc.stderr, (build / "build.ninja").read_text()


def gxx():
    path = shutil.which("g++")
    if path is None:
        pytest.fail("g++ is needed to build the core")
    return path


def test_a_compiler_that_cannot_link_with_lto_builds_without_it(tmp_path):
    wrapper = tmp_path / "bin" / "g++"
    wrapper.parent.mkdir()
    wrapper.write_text(BROKEN_LTO_GXX.format(gxx=gxx()))
    wrapper.chmod(0o755)
    log, ninja = configure(tmp_path / "build", f"-DCMAKE_CXX_COMPILER={wrapper}")
    assert "link-time optimisation off" in log and "could not run lto-wrapper" in log, log[-3000:]
    assert "-flto" not in ninja


def test_a_working_compiler_keeps_lto_on(tmp_path):
    log, ninja = configure(tmp_path / "build", f"-DCMAKE_CXX_COMPILER={gxx()}")
    assert "link-time optimisation on" in log, log[-3000:]
    assert "-flto" in ninja
