"""The verification commands as functions: compare, converge, validate, estimate_irradiance,
estimate_radiance, compare_modes. Statistical checks use the estimators' own standard errors."""

import numpy as np
import pytest

from conftest import SCENES, Z, candela, cli_render, scene_expected
from test_images import decode_png

VALIDATION_CBOX = SCENES / "validation" / "cbox.xml"


@pytest.fixture(scope="module")
def two_renders():
    scene = candela.load_file(VALIDATION_CBOX, res=32)
    return candela.render(scene, spp=4, seed=1), candela.render(scene, spp=16, seed=2)


def test_compare_metrics(two_renders):
    test, reference = two_renders
    result = candela.compare(test, reference)
    x, y = np.asarray(test, dtype=np.float64), np.asarray(reference, dtype=np.float64)
    # The metrics as docs/verification.md defines them (relMSE and MARE with an epsilon of 0.01).
    assert result["rmse"] == pytest.approx(np.sqrt(np.mean((x - y) ** 2)), rel=1e-6)
    assert result["relmse"] == pytest.approx(np.mean((x - y) ** 2 / (y * y + 1e-2)), rel=1e-6)
    assert result["mare"] == pytest.approx(np.mean(np.abs(x - y) / (y + 1e-2)), rel=1e-6)
    assert np.allclose(result["mean_test"], x.mean(axis=(0, 1)), rtol=1e-6)
    assert np.allclose(result["mean_reference"], y.mean(axis=(0, 1)), rtol=1e-6)
    assert np.allclose(result["mean_relative_difference"], x.mean(axis=(0, 1)) / y.mean(axis=(0, 1)) - 1, rtol=1e-5)
    assert result["blocks_total"] == 4 and 0 < result["blocks_used"] <= 4
    assert isinstance(result["heatmap"], candela.Image) and result["heatmap"].shape[2] == 3
    assert decode_png(result["heatmap"]._repr_png_()).shape == result["heatmap"].shape


def test_compare_verdicts(two_renders, tmp_path):
    test, _ = two_renders
    same = candela.compare(test, test)
    assert same["rmse"] == 0 and same["relmse"] == 0 and same["mare"] == 0
    assert same["agree"] and same["reason"] == ""
    scaled = candela.compare(test * 1.1, test)
    assert not scaled["agree"]
    assert "mean differs" in scaled["reason"]
    assert np.allclose(scaled["mean_relative_difference"], 0.1, rtol=1e-4)
    # EXR paths and plain arrays are accepted.
    candela.write_image(tmp_path / "t.exr", test)
    assert candela.compare(tmp_path / "t.exr", np.asarray(test))["rmse"] == 0
    with pytest.raises(ValueError, match="block_size"):
        candela.compare(test, test, block_size=0)


def test_converge_to_the_exact_value():
    path = SCENES / "furnace" / "closed_sphere.xml"
    expected = scene_expected(path)
    result = candela.converge(candela.load_file(path, res=16), spp=(4, 16, 64), expected=expected, seed=3)
    assert [c["spp"] for c in result["counts"]] == [4, 16, 64]
    for c in result["counts"]:
        # Unbiased: each count's bias within Z of its standard error.
        assert abs(c["bias"]) <= Z * c["bias_se"], c
        assert c["rmse"] > 0 and c["relmse"] > 0
    rmse = [c["rmse"] for c in result["counts"]]
    assert rmse == sorted(rmse, reverse=True)
    # Monte Carlo: RMSE ~ spp^-1/2, within Z standard errors of the fitted slope.
    assert result["slope_fitted"]
    assert abs(result["slope"] + 0.5) <= Z * result["slope_se"], (result["slope"], result["slope_se"])
    assert result["converges"] and result["failures"] == []
    plot = result["plot"]
    assert isinstance(plot, candela.Image) and plot.ndim == 3
    assert decode_png(plot._repr_png_()).shape == plot.shape


def test_converge_to_a_reference_and_bad_arguments():
    scene = candela.load_file(VALIDATION_CBOX, res=16)
    reference = candela.render(scene, spp=256, seed=100)
    result = candela.converge(scene, spp=(4, 16), reference=reference)
    assert len(result["counts"]) == 2 and result["counts"][0]["rmse"] > result["counts"][1]["rmse"]
    with pytest.raises(ValueError, match="exactly one"):
        candela.converge(scene, spp=(4,))
    with pytest.raises(ValueError, match="exactly one"):
        candela.converge(scene, spp=(4,), expected=1.0, reference=reference)
    with pytest.raises(ValueError, match="at least 1"):
        candela.converge(scene, spp=(0, 4), expected=1.0)


def test_validate_against_the_reference_render(tmp_path):
    result = candela.validate(VALIDATION_CBOX, SCENES / "validation" / "refs" / "cbox.exr", spp=16)
    assert result["name"] == "cbox" and result["spp"] == 16
    assert isinstance(result["passed"], bool)
    assert result["passed"] == (result["reason"] == "")
    assert np.allclose(np.asarray(result["mean_relative_difference"]),
                       np.asarray(result["mean_test"]) / np.asarray(result["mean_reference"]) - 1, rtol=1e-4, atol=1e-6)
    assert result["blocks_total"] == 256 and 0 <= result["z_rejected"] <= result["z_tested"]
    # The render it validates is the command line's render of the scene at that sample count.
    reference = candela.read_image(SCENES / "validation" / "refs" / "cbox.exr")
    ours = cli_render(VALIDATION_CBOX, tmp_path / "cli.exr", 16, 0)
    direct = candela.compare(ours, reference)
    assert result["rmse"] == pytest.approx(direct["rmse"], rel=1e-6)
    assert result["block_mare"] == pytest.approx(direct["block_mare"], rel=1e-6)


def test_estimate_irradiance_of_a_point_light():
    # A point light of intensity 3 at the centre of a black sphere of radius 2: E = 3 / 2^2 at
    # every point of the sphere facing the light, exactly (no randomness: one light, no bounce).
    scene = candela.load_file(SCENES / "furnace" / "point_irradiance.xml")
    points = np.array([[0, 0, 2], [2, 0, 0], [0, -2, 0]], dtype=np.float32)
    result = candela.estimate_irradiance(scene, points, -points / 2, samples=256)
    assert result["mean"].shape == (3, 3) and result["std_error"].shape == (3, 3)
    assert np.all(np.abs(result["mean"] - 0.75) <= Z * result["std_error"] + 1e-5 * 0.75)
    assert np.all(result["ci95_low"] <= result["mean"]) and np.all(result["mean"] <= result["ci95_high"])
    # Facing away from the light: nothing arrives.
    away = candela.estimate_irradiance(scene, points[:1], points[:1] / 2, samples=64)
    assert np.all(away["mean"] == 0)


def test_estimate_irradiance_under_a_uniform_sky():
    scene = candela.load_file(SCENES / "furnace" / "sky_irradiance.xml")
    expected = scene_expected(SCENES / "furnace" / "sky_irradiance.xml")  # pi L
    result = candela.estimate_irradiance(scene, [[0, 0, 0], [1, 0, 2]], [[0, 1, 0], [0, 1, 0]], samples=4096, seed=5)
    assert np.all(result["std_error"] > 0)
    assert np.all(np.abs(result["mean"] - expected) <= Z * result["std_error"])
    np.testing.assert_allclose(result["ci95_high"] - result["ci95_low"], 2 * 1.96 * result["std_error"], rtol=1e-5)


def test_estimate_radiance_of_a_convex_diffuse_object():
    scene = candela.load_file(SCENES / "furnace" / "convex_diffuse.xml")
    expected = scene_expected(SCENES / "furnace" / "convex_diffuse.xml")  # rho L
    result = candela.estimate_radiance(scene, [0, 0, 1.5], [0, 0, -1], samples=4096, seed=2)
    assert result["mean"].shape == (3,)
    assert np.all(result["std_error"] > 0)
    assert np.all(np.abs(result["mean"] - expected) <= Z * result["std_error"])
    # A ray that misses the sphere sees the environment: L exactly.
    sky = candela.estimate_radiance(scene, [0, 0, 1.5], [0, 0, 1], samples=64)
    assert np.allclose(sky["mean"], 1.5) and np.all(sky["std_error"] == 0)


def test_compare_modes():
    scene = candela.load_file(SCENES / "cbox.xml", res=16)
    result = candela.compare_modes(scene, methods=["raster", "path"], spp=4, reference_spp=64)
    methods = result["methods"]
    assert [m["method"] for m in methods] == ["raster", "path"]
    for m in methods:
        assert isinstance(m["image"], candela.Image) and m["image"].shape == (16, 16, 3)
        assert isinstance(m["heatmap"], candela.Image)
        assert m["relmse"] >= 0 and m["seconds"] >= 0
    assert isinstance(result["reference"], candela.Image) and result["reference"].shape == (16, 16, 3)
    assert isinstance(result["sheet"], candela.Image)
    assert "| raster |" in result["table"] and "| path |" in result["table"]
    # The raster method is the raster integrator's image.
    raster = candela.render(scene, integrator="raster")
    assert np.array_equal(np.asarray(methods[0]["image"]), np.asarray(raster))
