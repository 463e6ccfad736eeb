"""docs/python_tour.ipynb, executed with nbclient in Debian's python3 kernel: every cell runs, the
images it shows are there (image/png outputs that decode to pictures of the expected size), and the
numbers it prints are right."""

import base64
import math
import os
import re

import numpy as np
import pytest

from conftest import PYTHON_DIR, REPO, Z
from test_images import decode_png

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOK = REPO / "docs" / "python_tour.ipynb"


@pytest.fixture(scope="module")
def executed():
    notebook = nbformat.read(str(NOTEBOOK), as_version=4)
    for cell in notebook.cells:
        if cell.cell_type == "code":
            cell.outputs = []  # what is checked is this run's output, not the stored one
    saved = {k: os.environ.get(k) for k in ("PYTHONPATH", "PYDEVD_DISABLE_FILE_VALIDATION")}
    os.environ["PYTHONPATH"] = os.pathsep.join([str(PYTHON_DIR)] + ([saved["PYTHONPATH"]] if saved["PYTHONPATH"] else []))
    os.environ["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"
    try:
        client = nbclient.NotebookClient(notebook, timeout=120, kernel_name="python3",
                                         resources={"metadata": {"path": str(NOTEBOOK.parent)}})
        client.execute()
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    cells = {}
    for cell in notebook.cells:
        if cell.cell_type == "code":
            for tag in cell.metadata.get("tags", []):
                cells[tag] = cell
    return cells


def text_of(cell):
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream" and o.name == "stdout")


def images_of(cell):
    pictures = []
    for o in cell.outputs:
        if o.output_type in ("execute_result", "display_data") and "image/png" in o.get("data", {}):
            pictures.append(decode_png(base64.b64decode(o.data["image/png"])))
    return pictures


def test_every_cell_ran_without_error(executed):
    assert set(executed) >= {"setup", "render", "numbers", "edit", "raster", "converge"}
    for tag, cell in executed.items():
        assert not [o for o in cell.outputs if o.output_type == "error"], tag


@pytest.mark.parametrize("tag, shape", [
    ("render", (128, 128, 3)),
    ("edit", (128, 128, 3)),
    ("raster", (128, 256, 3)),
])
def test_images_are_shown(executed, tag, shape):
    pictures = images_of(executed[tag])
    assert len(pictures) == 1, f"{tag}: expected one image/png output"
    assert pictures[0].shape == shape
    assert pictures[0].max() > 0  # not a black picture


def test_render_numbers(executed):
    text = text_of(executed["numbers"])
    assert "shape (128, 128, 3) float32" in text
    assert "no copy: True" in text


def test_edit_changes_the_wall(executed):
    text = text_of(executed["edit"])
    assert "red.reflectance.value" in text
    m = re.search(r"left wall before \[([^\]]+)\] after \[([^\]]+)\]", text)
    before, after = (np.array([float(x) for x in g.split()]) for g in m.groups())
    assert before[0] > before[2] and after[2] > after[0]  # red before, blue after
    # The edited picture shows it too: the left wall's pixels are bluer than red.
    wall = images_of(executed["edit"])[0][40:90, 5:20].astype(float).mean(axis=(0, 1))
    assert wall[2] > wall[0]


def test_raster_comparison_numbers(executed):
    text = text_of(executed["raster"])
    relmse = float(re.search(r"relMSE \(raster vs path\): ([0-9.eE+-]+)", text).group(1))
    # Raster mode leaves out interreflection: clearly different from path tracing, finitely so.
    assert math.isfinite(relmse) and 0 < relmse < 10
    differences = re.search(r"mean relative difference per channel: \[([^\]]+)\]", text).group(1).split()
    assert all(-1 < float(d) < 0 for d in differences)  # darker without indirect light


def test_convergence_slope(executed):
    text = text_of(executed["converge"])
    slope, se = (float(x) for x in re.search(r"slope = ([-0-9.]+) \+- ([0-9.]+)", text).groups())
    assert abs(slope + 0.5) <= Z * se, (slope, se)
    assert "converges: True" in text
    rows = re.findall(r"spp +(\d+): RMSE ([0-9.]+), bias ([-+0-9.]+) \+- ([0-9.]+)", text)
    assert [int(r[0]) for r in rows] == [4, 16, 64, 256]
    for _, _, bias, bias_se in rows:
        assert abs(float(bias)) <= Z * float(bias_se) + 1e-5
    plot = images_of(executed["converge"])
    assert len(plot) == 1 and plot[0].shape[0] > 100 and plot[0].shape[1] > 100
