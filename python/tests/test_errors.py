"""Bad arguments raise ValueError, unreadable files OSError, with the library's message;
nothing crashes the interpreter."""

import numpy as np
import pytest

import omnicloud
from conftest import SAMPLE


def floor(n=1000):
    rng = np.random.default_rng(1)
    return np.column_stack([rng.uniform(-5, 5, n), rng.uniform(-5, 5, n), np.zeros(n)])


@pytest.mark.parametrize(
    "xyz, message",
    [
        (floor().astype(np.int32), "float64 or float32"),
        (floor()[:, :2], "(N, 3)"),
        ("not an array", "(N, 3)"),
    ],
)
def test_wrong_arrays_are_value_errors(xyz, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        omnicloud.PointCloud.from_arrays(xyz)


def test_a_nan_coordinate_names_its_row():
    xyz = floor()
    xyz[17, 2] = np.nan
    with pytest.raises(ValueError, match="xyz row 17 is not finite"):
        omnicloud.PointCloud.from_arrays(xyz)


def test_attribute_lengths_must_match():
    with pytest.raises(ValueError, match="rgb must be an"):
        omnicloud.PointCloud.from_arrays(floor(), rgb=np.zeros((3, 3), np.uint8))
    with pytest.raises(ValueError, match="intensity has 5 values for 1000 points"):
        omnicloud.PointCloud.from_arrays(floor(), intensity=np.zeros(5, np.uint16))


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(projection="mercator"), "projection"),
        (dict(stereo="sideways"), "unknown stereo"),
        (dict(width=7), "width"),
        (dict(renderer="magic"), "renderer"),
        (dict(ipd=-1.0), "ipd"),
        (dict(camera="somewhere"), "camera"),
        (dict(camera=(1.0, 2.0)), "camera"),
        (dict(pole_merge="sometimes"), "pole_merge"),
        (dict(classes="ground"), "classes"),
        (dict(classes=[2]), "classification"),
        (dict(projection="map", stereo="ods"), "one eye"),
    ],
)
def test_bad_render_arguments_are_value_errors(options, message):
    cloud = omnicloud.PointCloud.from_arrays(floor())
    with pytest.raises(ValueError, match=message):
        omnicloud.render(cloud, **{"width": 64, "renderer": "raytrace", **options})


def test_missing_and_unreadable_files_are_os_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.laz"):
        omnicloud.read(tmp_path / "nowhere.laz")
    bad = tmp_path / "bad.las"
    bad.write_bytes(b"not a las file at all")
    with pytest.raises(OSError, match="bad.las"):
        omnicloud.read(bad)


def test_saving_to_an_unknown_format_is_a_value_error(tmp_path):
    cloud = omnicloud.PointCloud.from_arrays(floor())
    image = omnicloud.render(cloud, width=32, renderer="raytrace", camera=(0.0, 0.0, 1.7))
    with pytest.raises(ValueError, match="gif"):
        image.save(tmp_path / "pano.gif")
    with pytest.raises(OSError):
        image.save(tmp_path / "missing-folder" / "pano.png")


def test_a_failing_progress_callback_raises_its_exception():
    cloud = omnicloud.read(SAMPLE)

    def progress(done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        omnicloud.render(cloud, width=256, renderer="raytrace", progress=progress)
