"""Python renders are the command line's renders: the same bytes for the same options."""

import numpy as np
import pytest

import omnicloud
from conftest import SAMPLE

# Small enough for the software Vulkan adapter and the ray tracer in CI.
WIDTH = 128


@pytest.mark.parametrize(
    "options, args",
    [
        (dict(), []),
        (dict(stereo="ods"), ["--stereo", "ods"]),
        (dict(renderer="raytrace"), ["--renderer", "raytrace"]),
        (dict(renderer="raytrace", stereo="ods", yaw=30.0), ["--renderer", "raytrace", "--stereo", "ods", "--yaw", "30"]),
    ],
    ids=["raster-mono", "raster-ods", "raytrace-mono", "raytrace-ods-yaw"],
)
def test_the_sample_renders_to_the_clis_png_byte_for_byte(tmp_path, cli, sample, options, args):
    ours = tmp_path / "python.png"
    theirs = tmp_path / "cli.png"
    image = omnicloud.render(sample, width=WIDTH, **options)
    assert image.save(ours) == [ours]
    cli("render", SAMPLE, "--width", WIDTH, "-o", theirs, "-q", *args)
    assert ours.read_bytes() == theirs.read_bytes()
    eyes = 2 if options.get("stereo") == "ods" else 1
    assert image.rgba.shape == (WIDTH // 2 * eyes, WIDTH, 4)
    assert image.depth.shape == (WIDTH // 2 * eyes, WIDTH)
    hit = image.rgba[..., 3] == 255
    # The camera stands in open space above ground: most of the lower half is covered.
    assert 0.3 < hit.mean() < 0.9, hit.mean()
    assert np.isinf(image.depth[~hit]).all() and np.isfinite(image.depth[hit]).all()


def test_stereo_images_split_into_eyes_and_compare_with_the_clis_file(tmp_path, cli, sample):
    image = omnicloud.render(sample, width=WIDTH, stereo="ods", renderer="raytrace")
    assert image.stereo and image.left.width == WIDTH and image.left.height == WIDTH // 2
    assert (image.left.rgba == image.rgba[: WIDTH // 2]).all()
    assert (image.right.rgba == image.rgba[WIDTH // 2 :]).all()
    # The eyes differ (parallax), but not by much.
    differ = (image.left.rgba != image.right.rgba).any(axis=2).mean()
    assert 0.001 < differ < 0.5, differ
    exr = tmp_path / "cli.exr"
    cli("render", SAMPLE, "--width", WIDTH, "--stereo", "ods", "--renderer", "raytrace", "-o", exr, "-q")
    ours = tmp_path / "ours.exr"
    image.save(ours)
    report = omnicloud.compare(exr, ours)
    assert report["layout"] == "top-bottom" and len(report["eyes"]) == 2
    assert all(e["all"]["mismatch"] == 0 for e in report["eyes"])
    same = omnicloud.compare(image, image)
    assert same["eyes"][0]["all"]["iou"] == 1.0
    png = image._repr_png_()
    assert png.startswith(b"\x89PNG") and len(png) > 1000


def test_a_cloud_from_arrays_renders_like_the_same_points_read_from_ply(tmp_path, cli):
    rng = np.random.default_rng(7)
    # A 20 m x 20 m floor of 40,000 coloured points around (1000, 2000, 50), with walls.
    n = 40_000
    xy = rng.uniform(-10, 10, size=(n, 2))
    z = np.where(rng.uniform(size=n) < 0.8, 0.0, rng.uniform(0, 3, size=n))
    xy[z > 0, 0] = np.sign(xy[z > 0, 0]) * 10
    xyz = np.column_stack([xy[:, 0] + 1000.0, xy[:, 1] + 2000.0, z + 50.0])
    rgb = rng.integers(0, 256, size=(n, 3), dtype=np.uint8)
    cloud = omnicloud.PointCloud.from_arrays(xyz, rgb=rgb)
    assert len(cloud) == n and cloud.unit == "metre"
    assert np.abs(cloud.xyz - xyz).max() < 1e-4
    assert (cloud.rgb == rgb).all()

    ply = tmp_path / "points.ply"
    with open(ply, "wb") as f:
        f.write(
            b"ply\nformat binary_little_endian 1.0\n"
            + f"element vertex {n}\n".encode()
            + b"property double x\nproperty double y\nproperty double z\n"
            + b"property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
        )
        record = np.zeros(n, dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"), ("r", "u1"), ("g", "u1"), ("b", "u1")])
        record["x"], record["y"], record["z"] = xyz.T
        record["r"], record["g"], record["b"] = rgb.T
        f.write(record.tobytes())
    for renderer in ["raster", "raytrace"]:
        ours, theirs = tmp_path / f"py_{renderer}.png", tmp_path / f"cli_{renderer}.png"
        omnicloud.render(cloud, width=WIDTH, camera=(1000.5, 2000.5, 51.7), renderer=renderer).save(ours)
        cli("render", ply, "--width", WIDTH, "--camera", "1000.5,2000.5,51.7", "--renderer", renderer, "-o", theirs, "-q")
        assert ours.read_bytes() == theirs.read_bytes(), renderer


def test_laspy_data_renders_like_the_file(tmp_path):
    laspy = pytest.importorskip("laspy")
    las = laspy.read(SAMPLE)
    cloud = omnicloud.PointCloud.from_laspy(las, unit="foot")
    read = omnicloud.read(SAMPLE)
    assert len(cloud) == len(read) == 110_000
    assert np.abs(cloud.xyz - read.xyz).max() < 1e-3
    assert (cloud.rgb == read.rgb).all()
    assert (cloud.classification == read.classification).all()
    a = omnicloud.render(cloud, width=64, renderer="raytrace")
    b = omnicloud.render(read, width=64, renderer="raytrace")
    # The float32 offsets differ (the file's origin is its header's centre, laspy's points'
    # the centre of their bounds), but not enough to move a pixel at this size (measured).
    assert a.camera == b.camera
    report = omnicloud.compare(b, a)
    assert report["eyes"][0]["all"]["mismatch"] == 0, report["eyes"][0]["all"]
    assert (a.rgba == b.rgba).all()


def test_filters_and_lengths_follow_the_command_line(tmp_path, cli, sample):
    ours, theirs = tmp_path / "py.png", tmp_path / "cli.png"
    omnicloud.render(sample, width=WIDTH, classes=[2], ipd=0.1, stereo="ods", renderer="raytrace", background="black").save(ours)
    cli("render", SAMPLE, "--width", WIDTH, "--classes", "2", "--ipd", "0.1", "--stereo", "ods",
        "--renderer", "raytrace", "--background", "black", "-o", theirs, "-q")
    assert ours.read_bytes() == theirs.read_bytes()
    ground = omnicloud.read(SAMPLE, classes="2")
    assert 0 < len(ground) < len(sample) and set(np.unique(ground.classification)) == {2}
