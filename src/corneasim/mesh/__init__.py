"""Meshes: data structure, parametric eye geometry, meshers, quality, I/O.

The meshers, the quality report and the file functions live in their modules
(``geometry``, ``axisymmetric``, ``hexahedral``, ``quality``, ``io``, ``preview``) and are
re-exported here; meshio and matplotlib are imported only when a file or picture is written.
"""

from corneasim.mesh._mesh import HEXAHEDRON_FACES, QUAD_FACES, Mesh
from corneasim.mesh.axisymmetric import mesh_axisymmetric
from corneasim.mesh.geometry import EyeGeometry
from corneasim.mesh.hexahedral import mesh_3d
from corneasim.mesh.io import read_mesh, write_mesh
from corneasim.mesh.quality import check_elements, quality_report

__all__ = [
    "HEXAHEDRON_FACES",
    "QUAD_FACES",
    "EyeGeometry",
    "Mesh",
    "check_elements",
    "mesh_3d",
    "mesh_axisymmetric",
    "quality_report",
    "read_mesh",
    "write_mesh",
]
