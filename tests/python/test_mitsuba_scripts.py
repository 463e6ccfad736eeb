"""Scripts written like Mitsuba 3's getting-started tutorials (mitsuba_scripts/), each run as it
stands in a fresh interpreter, with only `import mitsuba as mi` changed to
`import candela.mitsuba as mi`; their images are compared with the command line's renders of the
same scenes."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import SCENES, assert_same_expectation, candela, cli_render, run_cli, subprocess_env
from test_images import decode_png

SCRIPTS = Path(__file__).parent / "mitsuba_scripts"


def run_script(name, cwd):
    """Runs a tutorial script in `cwd`, where scenes/ is the repository's scenes folder."""
    (cwd / "scenes").symlink_to(SCENES)
    result = subprocess.run([sys.executable, str(SCRIPTS / name)], cwd=cwd, capture_output=True, text=True,
                            env=subprocess_env(), timeout=120)
    assert result.returncode == 0, f"{name} failed:\n{result.stdout}\n{result.stderr}"
    return result


@pytest.mark.parametrize("name", sorted(p.name for p in SCRIPTS.glob("*.py")))
def test_scripts_change_only_the_import(name):
    text = (SCRIPTS / name).read_text()
    code = [line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    assert code.count("import candela.mitsuba as mi") == 1
    # Nothing else of Candela's: with `import mitsuba as mi` the script is a Mitsuba 3 script.
    assert not any("candela" in line for line in code if line != "import candela.mitsuba as mi")
    assert re.search(r"^import mitsuba", text, re.M) is None


def test_render_from_file(tmp_path):
    out = run_script("render_from_file.py", tmp_path)
    assert "rendered (32, 32, 3)" in out.stdout
    reference = cli_render(SCENES / "cbox.xml", tmp_path / "cli.exr", 16, 0, {"res": 32})
    image = candela.read_image(tmp_path / "my_first_render.exr")
    assert np.array_equal(np.asarray(image), np.asarray(reference))
    # The PNG is the command line's --png picture.
    run_cli("render", SCENES / "cbox.xml", "-o", tmp_path / "cli2.exr", "--png", "--spp", 16, "--seed", 0, "-D", "res=32", "-q")
    assert np.array_equal(decode_png((tmp_path / "my_first_render.png").read_bytes()),
                          decode_png((tmp_path / "cli2.png").read_bytes()))


def test_build_with_load_dict(tmp_path):
    out = run_script("build_with_load_dict.py", tmp_path)
    # The LLVM variant renders on the CPU, with a one-line notice.
    notices = [line for line in out.stderr.splitlines() if "llvm_ad_rgb" in line]
    assert len(notices) == 1 and "CPU" in notices[0]
    # The same scene written as XML (the dictionary's transforms as <translate>, <rotate>, <scale>,
    # <lookat>) and rendered by the command line. Its film is float16 (hdrfilm's default), so
    # the command line's EXR holds half floats; the script's EXR holds the float32 render.
    reference = np.asarray(cli_render(SCRIPTS / "build_with_load_dict.xml", tmp_path / "cli.exr", 16, 2))
    image = np.asarray(candela.read_image(tmp_path / "dict_scene.exr"))
    assert image.shape == reference.shape == (32, 48, 3)
    assert image.mean() > 0.05
    assert_same_expectation(image.astype(np.float16).astype(np.float32), reference, "load_dict scene vs XML")
    png = decode_png((tmp_path / "dict_scene.png").read_bytes())
    assert np.array_equal(png, candela.image.srgb8(image))


def test_edit_with_traverse(tmp_path):
    out = run_script("edit_with_traverse.py", tmp_path)
    assert "red.reflectance.value" in out.stdout and "PerspectiveCamera.x_fov" in out.stdout
    source = (SCENES / "cbox.xml").read_text()
    blue = tmp_path / "blue.xml"
    blue.write_text(source.replace('value="0.63, 0.065, 0.05"', 'value="0.01, 0.2, 0.9"'))
    wide = tmp_path / "wide.xml"
    wide.write_text(source.replace('<float name="fov" value="39.3077"/>', '<float name="fov" value="50"/>'))
    assert blue.read_text() != source and wide.read_text() != source
    blue_reference = cli_render(blue, tmp_path / "cli_blue.exr", 16, 0, {"res": 32})
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "blue_wall.exr")), np.asarray(blue_reference))
    assert np.array_equal(decode_png((tmp_path / "blue_wall.png").read_bytes()), blue_reference.to_srgb8())
    wide_reference = cli_render(wide, tmp_path / "cli_wide.exr", 16, 0, {"res": 32})
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "wide.exr")), np.asarray(wide_reference))


def test_render_spectral(tmp_path):
    out = run_script("render_spectral.py", tmp_path)
    assert "rendered (30, 40, 3) in scalar_spectral" in out.stdout
    assert out.stderr == ""  # scalar_spectral renders as itself: no notice
    # The same scene written as XML, rendered by the command line in the spectral variant (the
    # dictionary's transforms as <translate>, <rotate>, <scale>, <lookat>).
    reference = np.asarray(cli_render(SCRIPTS / "render_spectral.xml", tmp_path / "cli.exr", 16, 0,
                                      extra=("--variant", "scalar_spectral")))
    image = np.asarray(candela.read_image(tmp_path / "spectral_scene.exr"))
    assert image.shape == reference.shape == (30, 40, 3)
    assert np.all(np.isfinite(image)) and image.mean() > 0.05
    assert_same_expectation(image, reference, "spectral load_dict scene vs XML")
    # The ball's measured reflectance is green: so is the ball, in the picture's centre.
    r, g, b = image[12:18, 17:23].reshape(-1, 3).mean(axis=0)
    assert g > r and g > b
    png = decode_png((tmp_path / "spectral_scene.png").read_bytes())
    assert np.array_equal(png, candela.image.srgb8(image))
