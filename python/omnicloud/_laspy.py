"""The point records of a `laspy.LasData` that `PointCloud.from_laspy` reads in place."""

import numpy as np


def las_fields(las, unit):
    """Positional and keyword arguments of `PointCloud._from_las_records` for `las`: its
    packed records as bytes (a view, no copy), the byte offsets of the fields read from them,
    the scales and offsets, and the bit-field attributes laspy unpacks."""
    points = las.points
    records = np.ascontiguousarray(points.array)
    fields = {
        name: records.dtype.fields[name][1]
        for name in ["X", "Y", "Z", "red", "green", "blue", "intensity"]
        if name in records.dtype.fields
    }
    names = set(points.point_format.dimension_names)

    def field(name):
        return np.ascontiguousarray(points[name], dtype=np.uint8) if name in names else None

    args = (
        records.reshape(-1).view(np.uint8),
        records.dtype.itemsize,
        fields,
        [float(s) for s in las.header.scales],
        [float(o) for o in las.header.offsets],
    )
    kwargs = dict(
        classification=field("classification"),
        return_number=field("return_number"),
        number_of_returns=field("number_of_returns"),
        unit=unit,
    )
    return args, kwargs
