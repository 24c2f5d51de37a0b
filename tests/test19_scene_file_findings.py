"""Each scene-file finding of issue 16 as a test: junk does not blow up memory or
the error line, and each malformed file gets a clear error naming the file and
the line (NFF) or element (PLY), or reads as the user meant. Through the CLI
(render, info, validate) each gives one line `gridwalk: error: ...` and exit 2."""
import subprocess
import sys
import textwrap

import pytest

from gridwalk import cli
from gridwalk.io import SceneFileError, load_nff, load_scene

VIEW = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\n"          # lines 1-5
HEADER = ("ply\nformat ascii 1.0\n{comment}element vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")

# name: (file name, content, expected error (None: the file reads), where, phrase)
FINDINGS = {
    "bare_s_then_a_sphere": ("scene.nff", VIEW + "s\ns 0 0 0 1\n", ":6: ",
                             "'s' needs 4 numbers (x y z radius), but only 0 follow before the entity 's' "
                             "on line 7"),
    "unicode_and_control_separators_do_not_end_lines": (
        "scene.nff", "# a\u2028b \u0085 c \x0c d \x1c e \x1d f \x1e g\n" + VIEW + "s 0 0\x0c0 1\nq\n", ":8: ",
        "unknown entity 'q'"),
    "p_with_a_5000_digit_count": ("scene.nff", VIEW + "p " + "1" * 5000 + "\n", ":6: ",
                                  "a token of 5000 characters (at most 256)"),
    "p_with_a_200_digit_count": ("scene.nff", VIEW + "p " + "1" * 200 + "\n", ":6: ",
                                 "'p' expects a vertex count (an integer from 3 to 1000000), got "
                                 "'1111111111111111111111111111111111111111'... (200 characters)"),
    "underscore_in_a_number": ("scene.nff", VIEW + "s 0 0 0 1_0\n", ":6: ", "'s': bad number '1_0'"),
    "cone_base_is_its_apex": ("scene.nff", VIEW + "c 1 2 3 1 1 2 3 0.5\n", ":6: ",
                              "cone ('c'): the apex coincides with the base"),
    "sphere_at_1e30": ("scene.nff", VIEW + "s 1e30 0 0 1\n", ":6: ",
                       "sphere ('s'): it extends beyond +-1e30, which the core cannot represent"),
    "from_equals_at": ("scene.nff", "v\nfrom 1 2 3\nat 1 2 3\nup 0 0 1\nangle 40\ns 0 0 0 1\n", ":3: ",
                       "view: 'at' coincides with 'from' (1, 2, 3) (or lies too close to it for float32): "
                       "the camera has no viewing direction"),
    "up_along_the_view": ("scene.nff", "v\nfrom 0 -5 0\nat 0 0 0\nup 0 1 0\nangle 40\ns 0 0 0 1\n", ":4: ",
                          "view: 'up' is parallel to the viewing direction"),
    "resolution_100000_squared": ("scene.nff", VIEW + "resolution 100000 100000\ns 0 0 0 1\n", ":6: ",
                                  "view: 'resolution' width x height = 10000000000 pixels: more than the "
                                  "limit of 2^28"),
    "a_folder": ("folder.nff", None, ": ", "is a folder, not a scene file"),
    "a_second_view_block": ("scene.nff", VIEW + "s 0 0 0 1\n" + VIEW.replace("-5", "5"), ":7: ",
                            "a second 'v' view block (the first is on line 1); an NFF file has one view"),
    "ctrl_z_before_more_entities": ("scene.nff", VIEW + "s 0 0 0 1\n\x1as 1 1 1 1\n", ":7: ",
                                    "binary or non-ASCII data"),
    "ply_face_index_out_of_range": ("mesh.ply", HEADER.format(comment="") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                                    ": ", "element 'face' record 0 (line 13): uses vertex index 7"),
    "ply_coordinate_1e35": ("mesh.ply", HEADER.format(comment="") + "0 0 0\n1e35 0 0\n0 1 0\n3 0 1 2\n", ": ",
                            "element 'vertex' record 1 (line 11): the coordinate (1e+35, 0, 0) lies beyond "
                            "+-1e30"),
}


def make(tmp_path, name):
    file_name, content, _, _ = FINDINGS[name]
    path = tmp_path / file_name
    if content is None:
        path.mkdir()
    else:
        path.write_bytes(content.encode("utf-8"))
    return path


@pytest.mark.parametrize("name", sorted(FINDINGS))
def test_finding_gives_a_clear_error_naming_the_file_and_place(tmp_path, name):
    path = make(tmp_path, name)
    _, _, where, phrase = FINDINGS[name]
    with pytest.raises(SceneFileError) as err:
        load_scene(path)
    message = str(err.value)
    assert message.startswith(f"{path}{where}"), message
    assert phrase in message, message
    assert len(message) < 400 + len(str(path)) and "\n" not in message
    if name == "sphere_at_1e30":
        assert "radius" not in message and "radii" not in message


def test_a_bare_s_line_followed_by_its_numbers_is_a_sphere(tmp_path):
    path = tmp_path / "scene.nff"
    path.write_text(VIEW + "s\n0 0 0 1\n")                         # a stream of numbers, as SPD reads it
    assert load_nff(path)["sphere_radii"].tolist() == [1.0]


def test_unicode_and_control_separators_inside_comments_are_just_comment_text(tmp_path):
    path = tmp_path / "scene.nff"
    path.write_bytes(("# \u2028 \u0085 \x0c \x1c \x1d \x1e\n" + VIEW + "s 0 0 0 1 # \u2028 s 9 9 9 9\n")
                     .encode("utf-8"))
    assert load_nff(path)["sphere_radii"].tolist() == [1.0]


@pytest.mark.parametrize("tail", ["\x1a", "\x1a\r\n", "\x1a \n\n  ", "\n# a ^Z \x1a in a comment\n\x1a"])
def test_a_dos_end_of_file_mark_ends_the_file(tmp_path, tail):
    """DOS editors end a text file with ^Z (0x1a); with only blanks after it,
    it ends the file (it was refused as binary data), also where it falls on
    the edge of a chunk of the reader's."""
    from gridwalk.io.tokens import TokenStream
    path = tmp_path / "scene.nff"
    path.write_bytes((VIEW + "s 0 0 0 1\ns 3 0 0 2").encode() + tail.encode())
    assert load_nff(path)["sphere_radii"].tolist() == [1.0, 2.0]
    for chunk in range(3, 12):
        with open(path, "rb") as f:
            words = [t for tokens, _ in TokenStream(f, chunk_bytes=chunk).segments() for t in tokens]
        assert words[-5:] == [b"s", b"3", b"0", b"0", b"2"], chunk


JUNK = {   # file content (written sparse where it is zeros), error phrase
    "zeros_100MB.nff": (None, 100 << 20, ":1: binary or non-ASCII data, '\\x00\\x00"),
    "token_50MB_after_s.nff": (VIEW.encode() + b"s " + b"7" * (50 << 20), 0,
                               ":6: a token of more than 256 characters, '7777"),
    "comment_200MB.nff": (b"#", 200 << 20, ": no geometry"),
}
MEASURE = """
import sys
from gridwalk.io import SceneFileError, load_nff

def kib(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith(field))

with open("/proc/self/clear_refs", "w") as f:       # restart the peak (VmHWM) from here
    f.write("5")
before = kib("VmRSS")
try:
    load_nff(sys.argv[1])
except SceneFileError as err:
    message = str(err)
print((kib("VmHWM") - before) // 1024)
print(message)
"""


@pytest.mark.parametrize("name", sorted(JUNK))
def test_junk_is_refused_in_bounded_memory_with_a_short_message(tmp_path, name):
    head, size, phrase = JUNK[name]
    path = tmp_path / name
    with open(path, "wb") as f:
        f.write(head or b"")
        if size:
            f.truncate(size)                                         # zero bytes, sparse
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(MEASURE), str(path)], capture_output=True,
                         text=True, timeout=120, check=True).stdout.splitlines()
    grown_mb, message = int(out[0]), out[1]
    print(f"{name}: peak memory grew {grown_mb} MB; {message}")
    assert message.startswith(str(path)) and phrase in message
    assert len(message) < 300 + len(str(path))
    assert grown_mb < 16


COMMANDS = {"render": ["-o", "{out}"], "info": [], "validate": ["--rays", "10"]}


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("name", sorted(FINDINGS))
def test_cli_prints_one_error_line_and_exits_2(tmp_path, capsys, command, name):
    path = make(tmp_path, name)
    args = [a.format(out=tmp_path / "out.png") for a in COMMANDS[command]]
    assert cli.main([command, str(path), *args]) == 2
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"gridwalk: error: {path}"), err
    assert FINDINGS[name][3] in lines[0]
    assert not (tmp_path / "out.png").exists()


def test_cli_in_a_real_process_refuses_zeros_with_one_line(tmp_path):
    path = tmp_path / "zeros.nff"
    with open(path, "wb") as f:
        f.truncate(1 << 20)
    for command in COMMANDS:
        proc = subprocess.run([sys.executable, "-m", "gridwalk", command, str(path),
                               *[a.format(out=tmp_path / "o.png") for a in COMMANDS[command]]],
                              capture_output=True, text=True, timeout=60)
        assert proc.returncode == 2 and proc.stdout == ""
        assert proc.stderr.count("\n") == 1 and proc.stderr.startswith(f"gridwalk: error: {path}:1: binary")
        assert "Traceback" not in proc.stderr
