"""Mitsuba 3's sunsky emitter from Python, as its scripts use it: in a scene dictionary, its
parameters listed by mi.traverse and edited through SceneParameters.update(). A radiance meter
aimed at the sky reads the emitter's value along one ray, which is exact."""

import numpy as np
import pytest

import candela.mitsuba as mi


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")
    yield


def meter(direction):
    film = {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}, "component_format": "float32"}
    return {"type": "radiancemeter", "origin": [0, 0, 0], "direction": list(direction), "film": film}


def sky_scene(direction, **sunsky):
    sunsky["type"] = "sunsky"
    return mi.load_dict({"type": "scene", "integrator": {"type": "path"}, "sun": sunsky, "meter": meter(direction)})


def test_parameters_are_listed_and_the_sky_follows_their_edits():
    scene = sky_scene([0.3, 0.2, 0.9], sun_direction=[0.5, -0.2, 0.6])
    params = mi.traverse(scene)
    for key in ("sun.turbidity", "sun.sky_scale", "sun.sun_scale", "sun.albedo.value", "sun.sun_direction", "sun.to_world"):
        assert key in params
    before = mi.render(scene, spp=1)[0, 0].copy()
    assert np.all(before > 0)
    params["sun.sky_scale"] = 2.0
    params.update()
    np.testing.assert_allclose(mi.render(scene, spp=1)[0, 0], 2 * before, rtol=1e-6)
    # A brighter ground brightens the sky (the model's albedo term), channel by channel: here red
    # alone, the others keep their albedo of 0.3.
    params["sun.albedo.value"] = [0.9, 0.3, 0.3]
    params.update()
    after = mi.render(scene, spp=1)[0, 0]
    assert after[0] > 1.05 * 2 * before[0]
    np.testing.assert_allclose(after[1:], 2 * before[1:], rtol=1e-6)


def test_the_sun_moves_with_its_direction_and_is_read_only_when_a_time_gives_it():
    scene = sky_scene([0.0, 0.6, 0.8], sun_direction=[0.5, -0.2, 0.6])
    sky = mi.render(scene, spp=1)[0, 0].copy()
    params = mi.traverse(scene)
    params["sun.sun_direction"] = [0.0, 0.6, 0.8]
    params.update()
    sun = mi.render(scene, spp=1)[0, 0]
    # The meter now looks into the sun's disk: thousands of times the sky's radiance.
    assert np.all(sun > 1000 * sky)
    timed = mi.traverse(sky_scene([0, 0, 1], hour=10.0))
    assert "sun.hour" in timed and "sun.sun_direction" in timed
    direction = np.array(timed["sun.sun_direction"])
    assert abs(np.linalg.norm(direction) - 1) < 1e-5
    with pytest.raises(Exception):
        timed["sun.sun_direction"] = [0.0, 0.0, 1.0]
        timed.update()


def test_invalid_values_are_refused():
    with pytest.raises(Exception, match="turbidity"):
        sky_scene([0, 0, 1], turbidity=0.5)
    with pytest.raises(Exception, match="sun_direction and a time"):
        sky_scene([0, 0, 1], sun_direction=[0, 0, 1], hour=9.0)


def test_timed_sunsky_changes_over_the_shutter():
    # Ten days from 2025-03-01, 7:00 to 19:00 each, over a sensor shutter of [0, 1]: a meter
    # aimed at the zenith reads the sky at the instant its shutter gives (night at the window's
    # end, day in between); its parameters are listed under Mitsuba's names.
    def reading(time):
        film = {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}, "component_format": "float32"}
        sensor = {"type": "radiancemeter", "origin": [0, 0, 0], "direction": [0, 0, 1], "film": film,
                  "shutter_open": time, "shutter_close": time}
        scene = mi.load_dict({"type": "scene", "integrator": {"type": "path"}, "meter": sensor,
                              "sky": {"type": "timed_sunsky", "start_year": 2025, "start_month": 3, "end_year": 2025,
                                      "end_month": 3, "end_day": 11, "latitude": 46.5, "longitude": 6.6, "timezone": 1.0}})
        return scene, mi.render(scene, spp=1)[0, 0]

    scene, noon = reading(0.04)  # day 0, 7:00 + 12 h x 0.4 = 11:48
    _, evening = reading(0.0999)  # day 0, 18:59: the sun has set
    assert np.all(noon > 0) and np.all(evening == 0)
    params = mi.traverse(scene)
    for key in ("sky.window_start_time", "sky.window_end_time", "sky.start_year", "sky.end_day", "sky.latitude", "sky.turbidity"):
        assert key in params
