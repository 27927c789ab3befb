# Rendering from Python: the same image as the CLI, progress callbacks, cancellation (from the
# callback, from another thread, by Ctrl-C) and continuation, with the GIL released.
import _thread
import subprocess
import threading
import time

import numpy as np
import pytest

import facet
import tiny_scenes as ts


@pytest.fixture(scope="module")
def scene():
    return facet.load_scene_from_string(ts.scene_json(), name="tiny")


SLOW_SPP = 1024


def big_session(**options):
    # Slow enough to be interrupted: 1024 spp at 160 x 120 takes several seconds at 2 threads.
    scene = facet.load_scene_from_string(ts.scene_json(SLOW_SPP, 160, 120), name="slow")
    return scene, facet.RenderSession(scene, threads=2, **options)


def test_python_render_equals_the_cli(tmp_path, facet_cli):
    path = ts.write_scene(tmp_path, spp=6)
    exr = tmp_path / "cli.exr"
    subprocess.run([str(facet_cli), "render", str(path), "-o", str(exr), "-q"], check=True)
    cli = facet.read_image(str(exr))
    py = facet.render(facet.load_scene(str(path)))
    assert py.shape == cli.shape == (ts.HEIGHT, ts.WIDTH, 3)
    np.testing.assert_array_equal(py, cli)
    # Thread count and pass sizes do not change the image.
    np.testing.assert_array_equal(facet.render(facet.load_scene(str(path)), threads=1,
                                               pass_seconds=1e-9), cli)


def test_options_override_the_scene_and_bad_options_raise(scene):
    a = facet.render(scene, spp=2, seed=3, max_depth=2, integrator="direct")
    b = facet.render(scene, spp=2, seed=4, max_depth=2, integrator="direct")
    assert not np.array_equal(a, b)
    with pytest.raises(ValueError, match=r"^spp: must be >= 1"):
        facet.render(scene, spp=-1)
    with pytest.raises(ValueError, match=r"^samples: 3:2 must be a non-empty range"):
        facet.render(scene, samples=(3, 2))
    with pytest.raises(ValueError, match=r"^seed: expected an int >= 0, got -1"):
        facet.render(scene, seed=-1)
    with pytest.raises(ValueError, match="integrator"):
        facet.render(scene, integrator="pth")
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'sp' \(did you mean 'spp'"):
        facet.render(scene, sp=2)
    with pytest.raises(ValueError, match=r"region: expected \(x0, y0, x1, y1\)"):
        facet.render(scene, region=(0, 0, 4))
    with pytest.raises(TypeError, match="expected a facet.Scene"):
        facet.render(ts.numpy_description())


def test_light_selection_option_and_pmfs(tmp_path):
    # A sun over a 40 m ground and an area light beside the sphere the camera frames: by power
    # the sun takes almost every shadow ray, measured from the view the area light does
    # (LightDistribution::view; the C++ test ViewSelectionFollowsTheCameraAndKeepsTheMean
    # checks the means). The option picks the distribution: the images differ (same seed), the
    # pmfs sum to 1, uniform is 1/2 each, and a bad value is an error naming the option.
    scene = facet.load_scene_from_string("""{"format": "facet-scene", "version": 1,
        "camera": {"position": [0, -4, 2.5], "look_at": [0, 0, 0.5], "up": [0, 0, 1], "fov": 40,
                   "width": 24, "height": 18},
        "materials": {"white": {"model": "lambert", "reflectance": 0.7}},
        "shapes": [{"type": "quad", "material": "white",
                    "vertices": [[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]]},
                   {"type": "sphere", "center": [0, 0, 0.6], "radius": 0.6, "material": "white"},
                   {"type": "quad", "emission": 40, "material": "white",
                    "vertices": [[1, 0.5, 2], [1.5, 0.5, 2], [1.5, -0.5, 2], [1, -0.5, 2]]}],
        "lights": [{"type": "directional", "direction": [-0.3, 0.4, -0.8], "irradiance": 1}],
        "render": {"spp": 2, "max_depth": 2}}""", name="sel")
    power, view, uniform = (scene.light_pmfs(m) for m in ("power", "view", "uniform"))
    area = 0 if power[0] < power[1] else 1
    assert power[area] < 0.05 and view[area] > 0.5 and uniform == [0.5, 0.5]
    assert abs(sum(view) - 1) < 1e-6
    images = {m: facet.render(scene, light_selection=m, seed=1) for m in ("view", "power")}
    assert not np.array_equal(images["view"], images["power"])
    # The default, auto, is view with fewer than 12 local lights (here 1).
    np.testing.assert_array_equal(images["view"], facet.render(scene, seed=1))
    np.testing.assert_array_equal(images["view"], facet.render(scene, light_selection="auto",
                                                               seed=1))
    np.testing.assert_array_equal(facet.render(scene, uniform_light_selection=True, seed=1),
                                  facet.render(scene, light_selection="uniform", seed=1))
    # The light tree (per shaded point) is taken too; its choice is not a pmf per scene.
    tree = facet.render(scene, light_selection="tree", seed=1)
    assert tree.shape == images["view"].shape and np.isfinite(tree).all()
    with pytest.raises(ValueError,
                       match=r"^light_selection: expected 'auto', 'view', 'power', 'uniform' or "
                             r"'tree'"):
        facet.render(scene, light_selection="pwr")
    with pytest.raises(ValueError, match="selection"):
        scene.light_pmfs("pwr")


def test_progress_callback_sees_every_pass(scene):
    infos = []
    image = facet.render(scene, spp=8, pass_seconds=1e-9, progress=lambda i: infos.append(i))
    assert [i.pass_ for i in infos] == list(range(1, len(infos) + 1))
    assert infos[-1].samples_done == 8 and infos[-1].samples_target == 8
    assert all(a.samples_done < b.samples_done for a, b in zip(infos, infos[1:]))
    np.testing.assert_array_equal(image, facet.render(scene, spp=8))


def test_cancel_from_the_callback_then_continue(scene):
    session = facet.RenderSession(scene, spp=8, pass_seconds=1e-9)
    seen = []

    def on_pass(info):
        seen.append(session.samples_done)
        return info.samples_done < 2  # False cancels

    assert session.render(on_pass) is False
    assert session.stats.cancelled
    done = session.samples_done
    assert 2 <= done < 8
    partial = session.image()
    assert np.all(np.isfinite(partial))
    np.testing.assert_array_equal(partial, facet.render(scene, spp=8, samples=(0, done)))
    # A later render() continues from exactly there.
    assert session.render() is True
    np.testing.assert_array_equal(session.image(), facet.render(scene, spp=8))


def test_cancel_from_another_thread():
    scene, session = big_session()
    timer = threading.Timer(0.2, session.cancel)
    t0 = time.perf_counter()
    timer.start()
    finished = session.render()
    elapsed = time.perf_counter() - t0
    timer.join()
    assert finished is False and session.stats.cancelled
    assert elapsed < 2.0
    # 0 when the first pass had not completed everywhere (slow machines, sanitizers).
    assert 0 <= session.samples_done < SLOW_SPP
    assert np.all(np.isfinite(session.image()))


def test_gil_is_released_while_rendering():
    scene, session = big_session()
    ticks = []
    worker = threading.Thread(target=session.render)
    worker.start()
    t_end = time.perf_counter() + 0.3
    while time.perf_counter() < t_end:
        ticks.append(1)
        time.sleep(0.001)
    # Another thread cannot read the image while a pass renders.
    with pytest.raises(RuntimeError, match="running on another thread"):
        for _ in range(1000):
            session.image()
    session.cancel()
    worker.join()
    assert len(ticks) > 50  # the main thread ran Python during the render
    assert session.stats.cancelled


@pytest.mark.parametrize("with_callback", [False, True])
def test_ctrl_c_cancels_cleanly(with_callback):
    scene, session = big_session()
    timer = threading.Timer(0.2, _thread.interrupt_main)  # what Ctrl-C does
    calls = []
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        session.render((lambda info: calls.append(info)) if with_callback else None)
    elapsed = time.perf_counter() - t0
    timer.join()
    assert elapsed < 2.0
    # The render has stopped: the session is usable and holds a valid partial image.
    assert session.stats.cancelled
    assert 0 < session.samples_done < SLOW_SPP
    assert np.all(np.isfinite(session.image()))
    # Ctrl-C inside facet.render, no callback.
    timer = threading.Timer(0.2, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        facet.render(scene, threads=2)
    timer.join()


def test_callback_exception_cancels_and_propagates(scene):
    session = facet.RenderSession(scene, spp=8, pass_seconds=1e-9)

    def boom(info):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        session.render(boom)
    assert session.stats.cancelled and session.samples_done < 8


def test_continue_to_equals_a_fresh_render_of_the_total(scene):
    session = facet.RenderSession(scene, spp=3)
    assert session.render() is True
    np.testing.assert_array_equal(session.image(), facet.render(scene, spp=3))
    session.continue_to(10)
    assert session.render() is True
    assert session.samples_done == 10
    np.testing.assert_array_equal(session.image(), facet.render(scene, spp=10))
    with pytest.raises(ValueError):
        session.continue_to(4)
    assert session.settings.spp == 3  # the options' spp; the target is now 10


def test_images_round_trip_through_files(scene, tmp_path):
    image = facet.render(scene, spp=2)
    facet.write_image(image, str(tmp_path / "a.exr"))
    np.testing.assert_array_equal(facet.read_image(str(tmp_path / "a.exr")), image)
    facet.write_image(image, str(tmp_path / "a.png"))
    assert facet.read_image(str(tmp_path / "a.png")).shape == image.shape
    with pytest.raises(ValueError, match=r"image: shape \(30, 40\), expected \(h, w, 3\)"):
        facet.write_image(image[:, :, 0], str(tmp_path / "b.exr"))
    with pytest.raises(RuntimeError, match="nope.exr"):
        facet.read_image(str(tmp_path / "nope.exr"))


def test_adaptive_sampling_from_python_and_the_scene_settings():
    """adaptive_threshold as an option and as the scene's render setting (JSON round trip):
    fewer mean samples than the cap, the same image either way, and bad values name the
    option."""
    d = ts.numpy_description()
    r = d.render
    r.spp = 64
    d.render = r
    scene = facet.build_scene(d, name="plain")
    s = facet.RenderSession(scene, threads=2, adaptive_threshold=0.05, adaptive_min_samples=8)
    s.render()
    assert 8 <= s.stats.mean_spp < 64
    r.adaptive_threshold, r.adaptive_min_samples = 0.05, 8
    d.render = r
    twin = facet.parse_scene_description(d.to_json(), name="twin")
    assert twin.render.adaptive_threshold == 0.05 and twin.render.adaptive_min_samples == 8
    np.testing.assert_array_equal(facet.render(facet.build_scene(twin, name="a"), threads=1),
                                  np.asarray(s.image()))
    # The option overrides the scene's: 0 turns it off.
    off = facet.RenderSession(facet.build_scene(twin, name="b"), threads=2, adaptive_threshold=0)
    off.render()
    assert off.stats.mean_spp == 64
    with pytest.raises(ValueError, match=r"^adaptive_threshold: must be in \[0, 1\]"):
        facet.render(scene, adaptive_threshold=-1)
    with pytest.raises(ValueError, match="region"):
        facet.render(scene, adaptive_threshold=0.05, samples=(0, 8))
    with pytest.raises(ValueError, match="adaptive"):
        facet.render(scene, adaptive_threshold=0.05, denoise=True)


def test_session_depth_pass_is_the_aov_depth_of_its_samples(scene):
    # RenderSession(depth_pass=True).depth(): render_aovs' depth at the same spp and seed, bit
    # for bit (render.h); None without the option; render() has no session to keep it in.
    s = facet.RenderSession(scene, spp=4, seed=7, threads=2, depth_pass=True)
    s.render(None)
    depth = s.depth()
    want = facet.render_aovs(scene, ["depth"], spp=4, seed=7)["depth"]
    assert depth.shape == want.shape == (ts.HEIGHT, ts.WIDTH, 3)
    np.testing.assert_array_equal(depth, want)
    assert (depth[:, :, 0] < 1e9).any()  # something is hit (else the pass would be all misses)
    plain = facet.RenderSession(scene, spp=4, seed=7, threads=2)
    plain.render(None)
    assert plain.depth() is None
    with pytest.raises(ValueError, match=r"^depth_pass: only a RenderSession keeps"):
        facet.render(scene, spp=2, depth_pass=True)
