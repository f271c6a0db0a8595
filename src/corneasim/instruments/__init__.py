"""Rigid instruments: their shapes, prescribed motion, placement on the tissue and outline.

* shapes: :class:`Needle`, :class:`Trephine` (validated tables; ``pack()`` for the kernels),
  ``signed_distance`` / ``signed_distance_rz`` (Numba; ``_shapes``);
* motion: :class:`Motion` (insertion and rotation amplitudes), :class:`MotionConfig` (its
  table), ``pose_at`` and the named fields of the pose array (``POSE_*``; ``_motion``);
* placement: ``tip_height_for_gap``, ``edge_surface_height`` (``_placement``);
* outline: ``instrument_section``, the instrument's section for the stress maps (``_outline``).

Contact with the tissue: :mod:`corneasim.contact`. Theory and verification: ``docs/contact.md``.
"""

from corneasim.instruments._kinds import Needle, Trephine, instrument_from_dict
from corneasim.instruments._motion import (
    POSE_ANGLE, POSE_OMEGA, POSE_SIZE, POSE_VX, POSE_VY, POSE_VZ, POSE_X, POSE_Y, POSE_Z, Motion, MotionConfig,
    needle_insertion, pose_at, trephination)
from corneasim.instruments._outline import instrument_section
from corneasim.instruments._placement import edge_surface_height, tip_height_for_gap
from corneasim.instruments._shapes import BEVELLED, PROFILE, ROUNDED, signed_distance, signed_distance_rz

__all__ = [
    "BEVELLED", "PROFILE", "ROUNDED",
    "Motion", "MotionConfig", "Needle", "POSE_ANGLE", "POSE_OMEGA", "POSE_SIZE", "POSE_VX", "POSE_VY", "POSE_VZ",
    "POSE_X", "POSE_Y", "POSE_Z", "Trephine", "edge_surface_height", "instrument_from_dict", "instrument_section",
    "needle_insertion", "pose_at", "signed_distance", "signed_distance_rz", "tip_height_for_gap", "trephination",
]
