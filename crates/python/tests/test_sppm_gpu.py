"""Tests of the sppm_gpu package: every function, against the command line where both do the
same thing. Renders are small (32x32, few passes, few photons): each new renderer compiles
its kernels, which on lavapipe takes seconds.

Needs a GPU adapter (lavapipe will do); without one the GPU tests are skipped, except under
CI=true, where they fail. The bit-identity test runs the command line, target/release/sppm-gpu
(or $SPPM_GPU_BIN), which `cargo build --release` makes.
"""

import ast
import csv
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import sppm_gpu

ROOT = Path(__file__).resolve().parents[3]
SCENE = ROOT / "scenes" / "cornell-box.toml"
# The settings every small render here shares: 32x32, few photons a pass.
SMALL = dict(width=32, height=32, photons=20000)


def have_adapter():
    try:
        return len(sppm_gpu.adapters()) > 0
    except sppm_gpu.Error:
        return False


@pytest.fixture(scope="module")
def gpu():
    if not have_adapter():
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true and no GPU adapter")
        pytest.skip("no GPU adapter (install mesa-vulkan-drivers)")


@pytest.fixture(scope="module")
def scene():
    return sppm_gpu.load(SCENE)


def cli():
    binary = Path(os.environ.get("SPPM_GPU_BIN", ROOT / "target" / "release" / "sppm-gpu"))
    if not binary.exists():
        pytest.fail(f"{binary} is missing: run `cargo build --release` first")
    return binary


def test_load_reads_the_scene_settings(scene):
    assert (scene.width, scene.height, scene.method, scene.passes) == (256, 256, "sppm", 64)
    assert scene.path.endswith("cornell-box.toml")
    assert "cornell-box.toml" in repr(scene)


def test_load_passes_params_as_mitsuba_defines():
    path = ROOT / "scenes" / "mitsuba" / "plastic.xml"
    default = sppm_gpu.load(path)
    mine = sppm_gpu.load(path, res=24, spp=5)
    assert (mine.width, mine.height) == (24, 24) != (default.width, default.height)
    assert mine.passes == 5 != default.passes


def test_a_toml_scene_refuses_params():
    with pytest.raises(sppm_gpu.SceneError) as e:
        sppm_gpu.load(SCENE, res=24)
    assert e.value.file.endswith("cornell-box.toml")
    assert "res" in str(e.value)


def test_a_bad_scene_raises_scene_error_with_file_line_and_key(tmp_path):
    text = SCENE.read_text().replace("alpha = 0.6667", "alpha = 1.5")
    assert text != SCENE.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    line = 1 + text.splitlines().index("alpha = 1.5")
    with pytest.raises(sppm_gpu.SceneError) as e:
        sppm_gpu.load(bad)
    err = e.value
    assert (Path(err.file), err.line, err.key) == (bad, line, "render.alpha")
    assert "1.5" in err.message
    assert str(err).startswith(f"{bad}:{line}: key `render.alpha`")
    assert isinstance(err, sppm_gpu.Error)


def test_a_missing_scene_raises_scene_error(tmp_path):
    with pytest.raises(sppm_gpu.SceneError) as e:
        sppm_gpu.load(tmp_path / "none.toml")
    assert e.value.line is None and "cannot read" in e.value.message


def test_bad_settings_raise_setting_error_naming_the_keyword(scene):
    with pytest.raises(sppm_gpu.SettingError, match="^alpha must be between 0 and 1"):
        scene.render(alpha=2.0)
    with pytest.raises(sppm_gpu.SettingError, match="max_depth must be between 1 and 1024"):
        scene.render(max_depth=0)
    with pytest.raises(sppm_gpu.SettingError, match="^passes must be between 1 and"):
        scene.render(passes=0)
    with pytest.raises(sppm_gpu.SettingError, match="unknown method `nope`"):
        scene.render(method="nope")
    with pytest.raises(sppm_gpu.SettingError, match="every must be at least 1"):
        scene.progressive(every=0)
    with pytest.raises(TypeError):
        scene.render(colour="red")


# A value of each render setting, all of them valid together (a 16x16 SPPM render of two
# passes; the scene's own values where its kernels depend on them, so that it compiles none
# the other tests do not), and a value each refuses with what its error says. A setting of
# the package's table missing here fails test_the_settings_are_one_table.
GOOD = dict(
    method="sppm", passes=2, time_limit=60.0, seed=3, width=16, height=16, photons=5000, radius=0.05,
    alpha=0.7, spp=1, max_depth=64, direct="sampled", direct_samples=1, light_paths=256,
    connect_share=1.0, merge_share=1.0, radius_schedule="per-point", radius_rule="shrink", sampler="sobol",
)
BAD = dict(
    method=("nope", sppm_gpu.SettingError, "^unknown method `nope`"),
    passes=(0, sppm_gpu.SettingError, "^passes must be between 1 and"),
    time_limit=(-1.0, sppm_gpu.SettingError, "^time_limit must be a positive number"),
    seed=(-1, OverflowError, "^argument 'seed': "),
    width=(0, sppm_gpu.SettingError, "^width must be between 1 and"),
    height=(0, sppm_gpu.SettingError, "^height must be between 1 and"),
    photons=(0, sppm_gpu.SettingError, "^photons must be between 1 and"),
    radius=(-1.0, sppm_gpu.SettingError, "^radius must be a positive number"),
    alpha=(1.5, sppm_gpu.SettingError, "^alpha must be between 0 and 1"),
    spp=(0, sppm_gpu.SettingError, "^spp must be between 1 and 1024"),
    max_depth=(0, sppm_gpu.SettingError, "^max_depth must be between 1 and"),
    direct=("nope", sppm_gpu.SettingError, "^unknown direct `nope`"),
    direct_samples=(0, sppm_gpu.SettingError, "^direct_samples must be between 1 and"),
    # 0 is vcm without light subpaths; a negative count is no u32.
    light_paths=(-1, OverflowError, "^argument 'light_paths': "),
    connect_share=(1.5, sppm_gpu.SettingError, r"^connect_share must lie in \[0, 1\]"),
    merge_share=(-0.5, sppm_gpu.SettingError, r"^merge_share must lie in \[0, 1\]"),
    radius_schedule=("nope", sppm_gpu.SettingError, "^unknown radius_schedule `nope`"),
    radius_rule=("nope", sppm_gpu.SettingError, "^unknown radius_rule `nope`"),
    sampler=("nope", sppm_gpu.SettingError, "^unknown sampler `nope`"),
)
# The settings compare() refuses: it sets them itself. time_limit it takes as an argument of
# its own, not among its **params.
COMPARE_REFUSES = {"method", "passes", "direct"}
COMPARE_PARAMS = set(GOOD) - COMPARE_REFUSES - {"time_limit"}


def settings(call):
    """The settings `call` takes, as its TypeError for an unknown keyword lists them."""
    with pytest.raises(TypeError, match="got an unexpected keyword argument 'colour'") as e:
        call(colour="red")
    return str(e.value).split("; its settings are: ")[1].split(", ")


def stub_keys(name):
    """The keys the stubs' TypedDict `name` declares, with those of its bases."""
    stubs = ROOT / "crates" / "python" / "python" / "sppm_gpu" / "__init__.pyi"
    classes = {c.name: c for c in ast.parse(stubs.read_text()).body if isinstance(c, ast.ClassDef)}

    def keys(c):
        bases = [k for b in c.bases if isinstance(b, ast.Name) and b.id in classes for k in keys(classes[b.id])]
        return bases + [s.target.id for s in c.body if isinstance(s, ast.AnnAssign)]

    return set(keys(classes[name]))


def test_the_settings_are_one_table(scene):
    table = settings(scene.render)
    assert settings(scene.progressive) == table
    compared = settings(lambda **k: sppm_gpu.compare(scene, "none.exr", ["pt"], 1, **k))
    assert compared == [k for k in table if k not in COMPARE_REFUSES]
    # The tests' values, the stubs' TypedDicts, the docstring and the guide have every one.
    assert set(table) == set(GOOD) == set(BAD)
    assert set(table) == stub_keys("_RenderParams") and COMPARE_PARAMS == stub_keys("_CompareParams")
    guide = (ROOT / "docs" / "guide" / "python.md").read_text()
    for key in table:
        assert f"\n- {key}: " in sppm_gpu.Scene.render.__doc__, key
        assert f"`{key}`" in guide, key


def test_each_setting_reaches_its_own_check(scene):
    # Each bad value is refused by its own setting's check (or name), not another's: the
    # keyword sets its own field.
    for key, (value, error, message) in BAD.items():
        with pytest.raises(error, match=message):
            scene.render(**{key: value})
        with pytest.raises(error, match=message):
            scene.progressive(**{key: value})


def test_a_bad_keyword_or_type_raises_naming_it(scene):
    unknown = r"^Scene.render\(\) got an unexpected keyword argument 'colour'; its settings are: method, passes, "
    with pytest.raises(TypeError, match=unknown):
        scene.render(colour="red")
    with pytest.raises(TypeError, match=r"^Scene.progressive\(\) got an unexpected keyword argument 'pases'"):
        scene.progressive(pases=3)
    for key in GOOD:
        with pytest.raises(TypeError, match=f"^argument '{key}': "):
            scene.render(**{key: [1]})
    with pytest.raises(TypeError, match="^argument 'passes': 'float' object cannot be interpreted as an integer"):
        scene.render(passes=2.5)
    for key in COMPARE_REFUSES:
        with pytest.raises(TypeError, match=f"^compare\\(\\) got an unexpected keyword argument '{key}' \\("):
            sppm_gpu.compare(scene, "none.exr", ["pt"], 1, **{key: GOOD[key]})


@pytest.fixture(scope="module")
def cli_image(gpu, tmp_path_factory):
    """The command line's image of the Cornell box, 32x32, 3 passes of 20,000 photons, seed 7."""
    out = tmp_path_factory.mktemp("cli") / "cli.exr"
    subprocess.run(
        [cli(), SCENE, "--width", "32", "--height", "32", "--photons", "20000", "--iterations", "3",
         "--seed", "7", "-o", out],
        check=True, capture_output=True,
    )
    return sppm_gpu.read(out)


def test_render_matches_the_command_line_bit_for_bit(scene, cli_image):
    image = scene.render(passes=3, seed=7, **SMALL)
    assert image.shape == (32, 32, 3) and image.dtype == np.float32
    assert image.strides == (32 * 3 * 4, 3 * 4, 4) and image.flags["C_CONTIGUOUS"] and image.flags["WRITEABLE"]
    assert np.isfinite(image).all() and image.mean() > 0.01
    assert np.array_equal(image, cli_image)
    # Another seed is another image.
    assert not np.array_equal(scene.render(passes=3, seed=8, **SMALL), cli_image)


def test_every_setting_renders(scene, cli_image):
    image = scene.render(**GOOD)
    assert image.shape == (16, 16, 3) and image.mean() > 0
    assert [p for p, _ in scene.progressive(every=1, **GOOD)] == [1, 2]
    # None keeps the scene's setting: the command line's image, every other setting None.
    nones = dict.fromkeys(GOOD)
    assert np.array_equal(scene.render(**{**nones, **SMALL, "passes": 3, "seed": 7}), cli_image)
    compared = {k: GOOD[k] for k in COMPARE_PARAMS}
    rows = sppm_gpu.compare(scene, image, ["sppm"], time_limit=0.2, first_snapshot=0.1, **compared)
    assert rows and all(r["method"] == "sppm" for r in rows)


def test_progressive_images_refine_and_end_at_the_render(gpu, scene):
    passes, images = [], []
    counts = [0]
    done = threading.Event()

    def count():
        # Python runs beside the render: the GIL is released while it renders.
        while not done.is_set():
            counts[0] += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        run = scene.progressive(passes=8, seed=7, **SMALL)
        for p, image in run:
            passes.append(p)
            images.append(image)
        seconds = run.seconds
    finally:
        done.set()
        counter.join()
    assert passes == [1, 2, 4, 8]
    assert seconds > 0
    assert counts[0] > 100
    # Each doubling of the passes changes the estimate less: it converges.
    changes = [np.abs(b - a).mean() for a, b in zip(images, images[1:])]
    assert changes[0] > changes[1] > changes[2] > 0, changes
    # The images are one render's, refined in place: the last is render()'s of 8 passes.
    assert np.array_equal(images[-1], scene.render(passes=8, seed=7, **SMALL))


def test_progressive_every_and_time_limit(gpu, scene):
    run = scene.progressive(method="pt-nee", passes=6, every=3, seed=1, **SMALL)
    passes, first = next(run)
    # A render while the iterator waits, unfinished: it has a thread of its own. Its image of
    # 3 passes is render()'s of 3 passes.
    assert passes == 3 and np.array_equal(first, scene.render(method="pt-nee", passes=3, seed=1, **SMALL))
    assert [p for p, _ in run] == [6]
    timed = list(scene.progressive(method="pt-nee", time_limit=0.5, every=4, seed=1, **SMALL))
    # Every fourth pass, then the last within the limit.
    assert len(timed) >= 2 and all(p % 4 == 0 for p, _ in timed[:-1])
    assert [p for p, _ in timed] == sorted({p for p, _ in timed})


def test_write_and_read_exr_exactly_and_png_as_srgb(tmp_path):
    rng = np.random.default_rng(1)
    image = rng.uniform(0.0, 4.0, size=(5, 7, 3)).astype(np.float32)
    sppm_gpu.write(tmp_path / "a.exr", image)
    back = sppm_gpu.read(tmp_path / "a.exr")
    assert back.shape == (5, 7, 3) and back.dtype == np.float32 and np.array_equal(back, image)
    # A non-contiguous float64 view is converted.
    sppm_gpu.write(str(tmp_path / "b.exr"), image.astype(np.float64)[:, ::-1])
    assert np.array_equal(sppm_gpu.read(tmp_path / "b.exr"), image[:, ::-1])
    # PNG: sRGB, 8 bits, clamped to 1.
    ldr = rng.uniform(0.0, 1.0, size=(4, 6, 3)).astype(np.float32)
    sppm_gpu.write(tmp_path / "c.png", ldr)
    png = sppm_gpu.read(tmp_path / "c.png")
    assert png.shape == (4, 6, 3) and np.abs(png - ldr).max() < 0.01 and not np.array_equal(png, ldr)


def test_image_errors(tmp_path):
    with pytest.raises(sppm_gpu.ImageError) as e:
        sppm_gpu.read(tmp_path / "none.exr")
    assert e.value.file.endswith("none.exr")
    with pytest.raises(sppm_gpu.ImageError):
        sppm_gpu.write(tmp_path / "a.bmp", np.zeros((2, 2, 3)))
    with pytest.raises(TypeError, match="height, width, 3"):
        sppm_gpu.write(tmp_path / "a.exr", np.zeros((2, 2, 4)))


def test_adapters_and_adapter_argument(gpu, scene):
    found = sppm_gpu.adapters()
    assert all({"index", "name", "backend", "device_type", "driver"} <= set(a) for a in found)
    assert [a["index"] for a in found] == list(range(len(found)))
    with pytest.raises(sppm_gpu.GpuError):
        scene.render(adapter="no such adapter", **SMALL)
    by_index = scene.render(adapter=0, method="pt", passes=1, width=16, height=16)
    by_name = scene.render(adapter=found[0]["name"], method="pt", passes=1, width=16, height=16)
    assert np.array_equal(by_index, by_name) and by_index.mean() > 0


def test_compare_returns_the_figures_of_its_csv(scene, cli_image, tmp_path):
    rows = sppm_gpu.compare(
        scene, cli_image, methods=["sppm", "pt-nee"], time_limit=0.3, first_snapshot=0.15, out=tmp_path,
        adapter=0, **SMALL
    )
    assert {r["method"] for r in rows} == {"sppm", "pt-nee"}
    for r in rows:
        assert r["passes"] >= 1 and 0 < r["seconds"] and 0 < r["relMSE"] < 10 and r["RMSE"] > 0
    with open(tmp_path / "compare.csv") as f:
        table = list(csv.DictReader(f))
    assert [t["method"] for t in table] == [r["method"] for r in rows]
    for t, r in zip(table, rows):
        assert int(t["passes"]) == r["passes"]
        assert float(t["relMSE"]) == pytest.approx(r["relMSE"], rel=1e-5)
        assert float(t["seconds"]) == pytest.approx(r["seconds"], abs=1e-3)
    assert (tmp_path / "equal-time.png").exists()
    with pytest.raises(sppm_gpu.SettingError, match="unknown method"):
        sppm_gpu.compare(scene, cli_image, methods=["nope"], time_limit=1)
    with pytest.raises(sppm_gpu.SettingError, match="reference is 32x32"):
        sppm_gpu.compare(scene, cli_image, methods=["pt"], time_limit=1, width=16, height=16)


# Last: the pass it interrupts goes on on the device after the test, and would hold up the
# renders of the tests after it.
def test_ctrl_c_raises_keyboard_interrupt_within_a_pass(gpu, scene):
    # A pass of many photons takes a second or so on lavapipe (more photons on a faster
    # device); the interrupt comes well before the second pass ends and must not wait for it.
    # The first pass's time holds the kernels' compile (a cold shader cache on CI): the pass
    # timed is the second, and the third is interrupted.
    photons = 1_000_000
    for _ in range(4):
        run = scene.progressive(width=16, height=16, photons=photons, passes=3, every=1)
        next(run)
        compiled = run.seconds
        second, _ = next(run)
        pass_seconds = run.seconds - compiled
        if pass_seconds > 0.5:
            break
        run.close()
        photons = min(2**31, int(photons * 1.0 / max(pass_seconds, 1e-3)) + 1)
    assert second == 2 and pass_seconds > 0.5, f"a pass took {pass_seconds:.2f} s: too short to interrupt within"
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        next(run)
    waited = time.monotonic() - start
    timer.join()
    assert waited < 0.2 + min(0.5, pass_seconds / 2), f"KeyboardInterrupt after {waited:.2f} s, a pass {pass_seconds:.2f} s"
    # The iterator is over; the render stops after the pass on the device.
    assert list(run) == []
