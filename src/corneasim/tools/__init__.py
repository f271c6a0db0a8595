"""Rigid instruments (needle, trephine), their prescribed motion and their contact with the tissue.

* shapes: :class:`Needle`, :class:`Trephine` (``pack()`` for the kernels);
  ``signed_distance``/``signed_distance_rz`` (Numba);
* motion: :class:`Motion`, ``needle_insertion``, ``trephination``; amplitudes in
  :mod:`corneasim.tools.amplitudes`;
* contact: :class:`InstrumentContact` (the solver hook), :class:`ContactSettings`,
  :class:`Friction`, ``eval_contact`` (the kernel).

Theory, choices and verification: ``docs/contact.md``.
"""

from corneasim.tools.config import ContactSettings, MotionConfig
from corneasim.tools.contact import OUTPUT_NAMES, eval_contact
from corneasim.tools.friction import Friction, FrictionValidityWarning, needle_friction_force
from corneasim.tools.instruments import Needle, Trephine, instrument_from_dict
from corneasim.tools.interaction import InstrumentContact, nodal_contact_areas, stable_penalty_fraction
from corneasim.tools.motion import Motion, needle_insertion, pose_at, trephination
from corneasim.tools.shapes import signed_distance, signed_distance_rz

__all__ = [
    "ContactSettings", "Friction", "FrictionValidityWarning", "InstrumentContact", "Motion", "MotionConfig",
    "Needle", "OUTPUT_NAMES", "Trephine", "eval_contact", "instrument_from_dict", "nodal_contact_areas",
    "needle_friction_force", "needle_insertion", "pose_at", "signed_distance", "signed_distance_rz",
    "stable_penalty_fraction", "trephination",
]
