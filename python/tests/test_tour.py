"""Python tours are the command line's tours: the same frames, byte for byte, and the same
poses in tour.json; bad paths raise ValueError naming what is wrong."""

import json

import numpy as np
import pytest

import omnicloud
from conftest import ROOT, SAMPLE

WALK = ROOT / "data" / "tours" / "autzen_walk.csv"
# data/tours/autzen_walk.csv's keyframes (x, y: heights from the ground).
KEYFRAMES = np.array([[636400, 849100], [636600, 849250], [636800, 849200]])
# Small enough for the software Vulkan adapter and the ray tracer in CI.
WIDTH = 64


def frames(folder):
    return {f.name: f.read_bytes() for f in sorted(folder.glob("frame_*"))}


def cli_tour(cli, folder, path, *args):
    cli("tour", SAMPLE, "--path", path, "-o", folder, "-q", "--width", WIDTH, *args)
    return json.loads((folder / "tour.json").read_text())


def same_poses(ours, theirs):
    assert len(ours["frames"]) == len(theirs["frames"])
    for a, b in zip(ours["frames"], theirs["frames"]):
        assert a["file"] == b["file"]
        # The cloud is moved onto the tour's origin from its own (a second float32 rounding of
        # the points): the ground under the path, so the eye's height, differs by
        # 5e-5 ft at most (measured 4.5e-5).
        assert np.abs(np.subtract(a["position"], b["position"])).max() < 1e-3, (a, b)
        assert abs(a["yaw"] - b["yaw"]) < 1e-6 and a["pitch"] == b["pitch"]


@pytest.mark.parametrize(
    "options, args",
    [
        (dict(frames=3, renderer="raytrace"), ["--frames", "3", "--renderer", "raytrace"]),
        (
            dict(frames=3, stereo="ods", yaw=90.0, heading_smoothing=0.0),
            ["--frames", "3", "--stereo", "ods", "--yaw", "90", "--heading-smoothing", "0"],
        ),
        (
            dict(speed=25.0, fps=1.0, renderer="raytrace", height=3.0),
            ["--speed", "25", "--fps", "1", "--renderer", "raytrace", "--height", "3"],
        ),
    ],
    ids=["raytrace-frames", "raster-ods-yaw", "raytrace-speed-height"],
)
def test_a_tour_writes_the_frames_and_poses_the_cli_writes(tmp_path, cli, sample, options, args):
    theirs = cli_tour(cli, tmp_path / "cli", WALK, *args)
    ours = omnicloud.tour(sample, KEYFRAMES, output=tmp_path / "py", width=WIDTH, **options)
    assert ours == json.loads((tmp_path / "py" / "tour.json").read_text())
    cli_frames, py_frames = frames(tmp_path / "cli"), frames(tmp_path / "py")
    # 140.5 m of path: 3 frames, or one every 25 m (6 frames).
    assert len(cli_frames) == (3 if "frames" in options else 6)
    assert py_frames == cli_frames
    same_poses(ours, theirs)
    for key in ["origin", "width", "height", "stereo_layout", "format", "fps", "metres_per_unit"]:
        assert ours[key] == theirs[key], key
    assert abs(ours["length"] - theirs["length"]) < 1e-6
    assert ours["path"] == "<path array>" and ours["scan"] == theirs["scan"]


def test_without_a_folder_the_frames_come_back_as_images(tmp_path, cli, sample):
    # Keyframes with heights fly through them (here about 50 ft over the ground at the ends,
    # the middle one at eye height over the ground under it): as a CSV with an empty z.
    csv = tmp_path / "fly.csv"
    csv.write_text("x,y,z\n636400,849100,480\n636600,849250,\n636800,849200,470\n")
    theirs = cli_tour(cli, tmp_path / "cli", csv, "--frames", "4", "--renderer", "raytrace")
    path = np.array([[636400, 849100, 480], [636600, 849250, np.nan], [636800, 849200, 470]])
    images = omnicloud.tour(sample, path, frames=4, width=WIDTH, renderer="raytrace")
    assert len(images) == 4 and not (tmp_path / "py").exists()
    for i, (image, frame) in enumerate(zip(images, theirs["frames"])):
        assert (image.width, image.height) == (WIDTH, WIDTH // 2)
        assert np.abs(np.subtract(image.camera, frame["position"])).max() < 1e-3
        saved = tmp_path / f"py_{i}.png"
        image.save(saved)
        assert saved.read_bytes() == (tmp_path / "cli" / frame["file"]).read_bytes(), i
    assert images[0].camera[2] == 480.0 and images[-1].camera[2] == 470.0
    hit = images[0].rgba[..., 3] == 255
    # 50 ft over the ground most of the lower half is covered, the sky is not (measured
    # 0.446).
    assert 0.35 < hit.mean() < 0.5, hit.mean()


def test_a_rerun_skips_the_frames_written_and_reports_progress(tmp_path, sample):
    calls = []
    options = dict(output=tmp_path, frames=3, width=32, renderer="raytrace")
    omnicloud.tour(sample, KEYFRAMES, progress=lambda d, t: calls.append((d, t)), **options)
    assert calls[-1] == (3, 3), calls
    (tmp_path / "frame_000001.png").unlink()
    before = (tmp_path / "frame_000000.png").stat().st_mtime_ns
    calls.clear()
    omnicloud.tour(sample, KEYFRAMES, progress=lambda d, t: calls.append((d, t)), **options)
    assert calls[-1] == (1, 1), calls
    assert (tmp_path / "frame_000001.png").exists()
    assert (tmp_path / "frame_000000.png").stat().st_mtime_ns == before


@pytest.mark.parametrize(
    "path, message",
    [
        (KEYFRAMES[:, 0], r"\(K, 2\) or \(K, 3\) array"),
        (np.zeros((3, 4)), r"shape \(3, 4\)"),
        (np.array([["a", "b"], ["c", "d"]]), r"array of numbers"),
        (KEYFRAMES[:1], "at least two keyframes, got 1"),
        (np.array([[636400.0, np.nan], [636600.0, 849250.0]]), "path row 0: x and y must be finite"),
        (np.array([[636400, 849100, 400], [636600, 849250, np.inf]]), "path row 1: z must be finite"),
        (np.array([[636400, 849100], [636400, 849100]]), "at least two distinct points"),
        (np.array([[636400, 849100], [0, 0]]), r"<path array>: row 1: \(0, 0\) lies outside the scan's bounds"),
        (np.array([[-123.07, 44.05], [-123.06, 44.06]]), "longitude/latitude"),
    ],
    ids=["1-D", "4-columns", "strings", "one-row", "nan-x", "inf-z", "repeated", "outside", "degrees"],
)
def test_bad_paths_are_value_errors_naming_what_is_wrong(sample, path, message):
    with pytest.raises(ValueError, match=message):
        omnicloud.tour(sample, path, frames=2, width=32, renderer="raytrace")


@pytest.mark.parametrize(
    "options, message",
    [
        (dict(projection="map"), "no camera to move"),
        (dict(format="jpg", background="transparent"), "JPEG has no alpha"),
        (dict(format="gif"), "format: unknown value `gif`"),
        (dict(frames=0), "at least one frame"),
        (dict(frames=None, speed=-1.0), "speed: -1 must be greater than 0"),
        (dict(heading_smoothing=-2.0), "must not be negative"),
        (dict(stereo="sideways"), "unknown stereo"),
    ],
)
def test_bad_tour_options_are_value_errors(sample, options, message):
    with pytest.raises(ValueError, match=message):
        omnicloud.tour(sample, KEYFRAMES, **{"frames": 2, "width": 32, "renderer": "raytrace", **options})
