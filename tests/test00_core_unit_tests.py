"""The core's C++ unit tests (doctest, core/src/*_test.cpp beside the code
they test: mailbox wrap-around, permutations and scrambling, empty-space
distances, the triangle test's error bound, camera projections, primitive/box overlap) build and pass."""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "build" / "unit"
TEST_FILES = sorted((ROOT / "core" / "src").glob("*_test.cpp"))


def run(*argv, timeout=600):
    proc = subprocess.run([str(a) for a in argv], capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{' '.join(map(str, argv))} failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
    return proc.stdout


def test_core_unit_tests_build_and_pass():
    cmake = Path(sys.executable).parent / "cmake"
    run(cmake, "-S", ROOT / "core", "-B", BUILD, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
        f"-DPython_EXECUTABLE={sys.executable}", "-DGRIDWALK_UNIT_TESTS=ON")
    run(cmake, "--build", BUILD, "--target", "gridwalk_unit_tests", "--parallel", "2")
    out = run(BUILD / "gridwalk_unit_tests")
    cases = re.search(r"test cases:\s*(\d+)\s*\|\s*(\d+) passed\s*\|\s*(\d+) failed", out)
    assert cases, out
    declared = sum(len(re.findall(r"^TEST_CASE\(", f.read_text(), re.M)) for f in TEST_FILES)
    assert int(cases.group(1)) == int(cases.group(2)) == declared and int(cases.group(3)) == 0, out
    assert {f.stem for f in TEST_FILES} >= {"mailbox_test", "sampler_test", "empty_space_test", "triangle_test",
                                          "camera_test", "overlap_test"}
