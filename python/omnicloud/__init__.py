"""omnicloud: LiDAR point clouds to 360° equirectangular panoramas and omnidirectional-stereo
(ODS) pairs, rendered by omnicloud's GPU rasterizer or its exact CPU ray tracer.

    import omnicloud
    cloud = omnicloud.read("scan.laz")            # or PointCloud.from_arrays / from_laspy
    image = omnicloud.render(cloud, width=2048, stereo="ods")
    image.save("pano_360_TB.png")                  # exactly what `omnicloud render` writes
    image.rgba, image.depth                         # numpy arrays
    frames = omnicloud.tour(cloud, keyframes, frames=60, width=1024)   # a walk, as Images

`help(omnicloud.render)` lists every option; they are the command line's.
"""

from ._native import Image, PointCloud, compare, read, render, tour

__all__ = ["Image", "PointCloud", "compare", "read", "render", "tour"]
