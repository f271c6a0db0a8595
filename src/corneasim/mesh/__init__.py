"""Meshes: data structure, parametric eye geometry, meshers, quality, I/O."""

from corneasim.mesh._mesh import HEXAHEDRON_FACES, QUAD_FACES, Mesh

__all__ = ["HEXAHEDRON_FACES", "QUAD_FACES", "Mesh"]
