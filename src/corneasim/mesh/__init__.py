"""Meshes: data structure, parametric eye geometry, meshers, quality, surfaces, I/O.

The meshers, the quality report, the boundary faces and the file functions live in private
modules (``_geometry``, ``_axisymmetric``, ``_hexahedral``, ``_quality``, ``_surface``,
``_io``, ``_preview``, ``_lamellae``: the fibre frames of the stroma) and are exported here; meshio and matplotlib are imported only when a
file or picture is written.
"""

from corneasim.mesh._mesh import HEXAHEDRON_FACES, QUAD_FACES, Mesh
from corneasim.mesh._axisymmetric import AXISYMMETRIC_PRESETS, mesh_axisymmetric
from corneasim.mesh._geometry import EyeGeometry
from corneasim.mesh._hexahedral import SOLID_PRESETS, mesh_3d
from corneasim.mesh._lamellae import lamellar_frames
from corneasim.mesh._io import MeshConversion, read_mesh, write_mesh
from corneasim.mesh._preview import write_preview
from corneasim.mesh._quality import check_elements, element_measures, element_sizes, quality_report
from corneasim.mesh._surface import face_normal_z, face_size, face_table, point_over_face



def mesh_presets() -> frozenset[str]:
    """Names of the built-in generators' mesh density presets (the values of ``mesh.preset``):
    the axisymmetric eye's and those of every 3D meshing strategy."""
    return frozenset(AXISYMMETRIC_PRESETS).union(*SOLID_PRESETS.values())


__all__ = [
    "HEXAHEDRON_FACES",
    "QUAD_FACES",
    "EyeGeometry",
    "Mesh",
    "MeshConversion",
    "check_elements",
    "element_measures",
    "element_sizes",
    "face_normal_z",
    "face_size",
    "face_table",
    "lamellar_frames",
    "mesh_3d",
    "mesh_axisymmetric",
    "mesh_presets",
    "point_over_face",
    "quality_report",
    "read_mesh",
    "write_mesh",
    "write_preview",
]
