"""ParaView output: one VTU file per output time and a ``.pvd`` index of them.

The ``.pvd`` collection (a small XML file listing ``(time, file)`` pairs) is
rewritten atomically after every frame, so ParaView can open the time series even
while a run is going or after it failed. Deleted elements stay in the files with
cell data ``alive = 0``; hide them in ParaView with a *Threshold* filter on
``alive``. The nodes they leave behind are written where they last belonged to the mesh
(:mod:`corneasim.output._orphans`).

Every frame carries the names of the element blocks as field data, in the convention meshio
uses for named regions: one integer array per block, named after the block, holding the
block's index, the value of the cell data ``block`` on its elements (``epithelium = 0``,
``stroma = 1``, ...). meshio does not write field data to VTU files, so the arrays are added
to the XML as ASCII ``DataArray`` elements of a ``FieldData`` block.

A half model (the trephine's) can be written whole: each frame then holds the mesh and its
image under the symmetry that completed it, x' = D x with D = diag(``image``): (-1, -1, 1)
for the cyclic symmetry of order 2 about z (a rotation by 180 degrees), (1, -1, 1) for the
mirror plane y = 0. The image's vector point data are D v, its symmetric-tensor cell data
(6 components, [xx, yy, zz, xy, yz, zx]) D sigma D, i.e. sigma_ij times d_i d_j, and its
scalars are the same; cell data ``image`` is 0 on the model and 1 on the image (threshold it
to see the computed half). A reflection (det D < 0) reverses each hexahedron face's node
order so that the image's cells keep a positive volume. The nodes on the cut plane appear
twice (once per half).
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.etree import ElementTree
from xml.sax.saxutils import quoteattr

import numpy as np

from corneasim.output._files import atomic_write_text

MESHIO_CELL_TYPE = {"quad": "quad", "hexahedron": "hexahedron"}


def _points_3d(points: np.ndarray) -> np.ndarray:
    """VTK wants 3D points: axisymmetric (r, z) becomes (r, z, 0)."""
    if points.shape[1] == 3:
        return points
    return np.column_stack([points, np.zeros(len(points))])


def _vector_3d(values: np.ndarray) -> np.ndarray:
    if values.ndim == 2 and values.shape[1] == 2:
        return np.column_stack([values, np.zeros(len(values))])
    return values


REFLECTED_HEXAHEDRON = np.array([0, 3, 2, 1, 4, 7, 6, 5])
"""VTK hexahedron node order of a reflected cell that keeps its volume positive."""


def _imaged_point_data(values: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The model's and the image's point values: vectors (n, 3) as D v, others as they are."""
    if values.ndim == 2 and values.shape[1] == 3:
        return np.concatenate([values, values * d])
    return np.concatenate([values, values])


def _imaged_cell_data(values: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The model's and the image's cell values: symmetric tensors (n, 6) as D sigma D, others
    as they are."""
    if values.ndim == 2 and values.shape[1] == 6:
        signs = np.array([d[0] * d[0], d[1] * d[1], d[2] * d[2], d[0] * d[1], d[1] * d[2], d[2] * d[0]])
        return np.concatenate([values, values * signs])
    return np.concatenate([values, values])


class TimeSeriesWriter:
    """Write frames of point and cell data on a fixed mesh as ``NAME_0000.vtu`` + ``NAME.pvd``.

    Parameters
    ----------
    folder : path-like
        Output folder (created).
    points : ndarray, shape (n_nodes, 2 or 3)
        Reference coordinates, mm.
    cells : ndarray, shape (n_elements, 4 or 8)
        Connectivity.
    cell_type : str
        ``"quad"`` or ``"hexahedron"``.
    name : str
        Base name of the files.
    resume_time : float, optional
        Continue an existing series: keep its frames up to this time (s), drop later ones.
    image : sequence of 3 floats, optional
        For a 3D half model: the diagonal of the symmetry D (entries +-1) that makes the
        whole; every frame then holds the model and its image (module notes).
    block_names : sequence of str, optional
        Names of the element blocks, written as field data of every frame (module notes).
    """

    def __init__(self, folder, points, cells, cell_type: str, name: str = "fields",
                 resume_time: float | None = None, image=None, block_names=()):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.points = _points_3d(np.asarray(points, dtype=float))
        cells = np.asarray(cells)
        self.image = None
        if image is not None:
            d = np.asarray(image, dtype=float)
            if self.points.shape[1] != 3 or d.shape != (3,) or not np.all(np.abs(d) == 1.0):
                raise ValueError("image: a 3D mesh and three entries of +-1 expected")
            mirrored = cells[:, REFLECTED_HEXAHEDRON] if np.prod(d) < 0.0 and cells.shape[1] == 8 else cells
            cells = np.concatenate([cells, mirrored + len(self.points)])
            self.image = d
        self.cells = [(MESHIO_CELL_TYPE[cell_type], cells)]
        self.name = name
        self.field_data = block_field_data(block_names)
        self.frames: list[tuple[float, str]] = []
        index = self.folder / f"{name}.pvd"
        if resume_time is not None and index.exists():
            entries = ElementTree.parse(index).getroot().findall("./Collection/DataSet")
            self.frames = [(float(e.get("timestep")), e.get("file")) for e in entries
                           if float(e.get("timestep")) <= resume_time * (1 + 1e-12)]

    def write(self, time: float, point_data: dict, cell_data: dict, displace: np.ndarray | None = None) -> Path:
        """Write one frame; vectors with 2 components are padded to 3 for ParaView.

        Parameters
        ----------
        time : float
            Simulation time of the frame, s.
        point_data, cell_data : dict of str to ndarray
            Nodal and element fields (one value or vector per node / element).
        displace : ndarray, optional
            If given, the points are written in the deformed configuration.
        """
        points = self.points if displace is None else self.points + _vector_3d(displace)
        point_data = {key: _vector_3d(np.asarray(value)) for key, value in point_data.items()}
        cell_data = {key: np.asarray(value) for key, value in cell_data.items()}
        if self.image is not None:
            n_cells = len(self.cells[0][1]) // 2
            points = np.concatenate([points, points * self.image])
            point_data = {key: _imaged_point_data(value, self.image) for key, value in point_data.items()}
            cell_data = {key: _imaged_cell_data(value, self.image) for key, value in cell_data.items()}
            cell_data["image"] = np.repeat(np.array([0, 1], dtype=np.uint8), n_cells)
        import meshio  # deferred to the first frame: a run's start-up does not wait for it

        mesh = meshio.Mesh(points, self.cells, point_data=point_data,
                           cell_data={key: [value] for key, value in cell_data.items()})
        filename = f"{self.name}_{len(self.frames):04d}.vtu"
        temporary = self.folder / f".{filename}.tmp"
        # uncompressed binary: zlib made each frame of the default needle mesh 10x slower to
        # write (121 ms instead of 12 ms) for a file only a quarter smaller
        meshio.write(temporary, mesh, file_format="vtu", compression=None)
        if self.field_data:
            _insert_field_data(temporary, self.field_data)
        os.replace(temporary, self.folder / filename)
        self.frames.append((float(time), filename))
        self._write_index()
        return self.folder / filename

    def _write_index(self) -> None:
        entries = "\n".join(
            f'    <DataSet timestep="{time!r}" group="" part="0" file={quoteattr(filename)}/>'
            for time, filename in self.frames
        )
        text = (
            '<?xml version="1.0"?>\n'
            '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n"
            f"{entries}\n"
            "  </Collection>\n"
            "</VTKFile>\n"
        )
        atomic_write_text(self.folder / f"{self.name}.pvd", text)


def block_field_data(block_names) -> str:
    """The ``FieldData`` XML element naming the blocks: one Int64 array per block, its index."""
    if not block_names:
        return ""
    arrays = "".join(
        f'<DataArray type="Int64" Name={quoteattr(str(name))} NumberOfTuples="1" format="ascii">{index}'
        "</DataArray>\n" for index, name in enumerate(block_names))
    return f"<FieldData>\n{arrays}</FieldData>\n"


def _insert_field_data(path: Path, field_data: str) -> None:
    """Put ``field_data`` (XML text) first in the ``UnstructuredGrid`` element of the VTU file ``path``."""
    text = path.read_bytes()
    tag = b"<UnstructuredGrid>"
    at = text.index(tag) + len(tag)
    path.write_bytes(text[:at] + b"\n" + field_data.encode("utf-8") + text[at:].lstrip(b"\n"))
