"""XDMF 3 export with the heavy data inline as XML (ParaView reads it; no HDF5 library needed).

meshio's XDMF writer needs h5py even for XML data, which corneasim does not depend on.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

TOPOLOGY = {"quad": "Quadrilateral", "hexahedron": "Hexahedron"}


def _data_item(values: np.ndarray) -> str:
    values = np.asarray(values)
    kind, precision = ("Float", 8) if values.dtype.kind == "f" else ("Int", 8)
    shape = " ".join(str(n) for n in values.shape)
    rows = values.reshape(values.shape[0], -1)
    fmt = "%.12g" if kind == "Float" else "%d"
    body = "\n".join(" ".join(fmt % v for v in row) for row in rows.tolist())
    return (f'<DataItem DataType="{kind}" Precision="{precision}" Dimensions="{shape}" Format="XML">\n'
            f"{body}\n</DataItem>")


def write_xdmf(path: Path, points: np.ndarray, cell_type: str, cells: np.ndarray,
               cell_data: dict[str, np.ndarray], point_data: dict[str, np.ndarray]) -> None:
    """Write one uniform grid with scalar cell and point attributes."""
    parts = [
        '<?xml version="1.0"?>',
        '<Xdmf Version="3.0">',
        "<Domain>",
        '<Grid Name="corneasim" GridType="Uniform">',
        f'<Topology TopologyType="{TOPOLOGY[cell_type]}" NumberOfElements="{len(cells)}">',
        _data_item(cells.astype(np.int64)),
        "</Topology>",
        '<Geometry GeometryType="XYZ">',
        _data_item(points.astype(float)),
        "</Geometry>",
    ]
    for center, data in (("Cell", cell_data), ("Node", point_data)):
        for name, values in data.items():
            parts += [f'<Attribute Name={quoteattr(name)} AttributeType="Scalar" Center="{center}">',
                      _data_item(np.asarray(values).astype(np.int64)), "</Attribute>"]
    parts += ["</Grid>", "</Domain>", "</Xdmf>"]
    path.write_text("\n".join(parts) + "\n")
