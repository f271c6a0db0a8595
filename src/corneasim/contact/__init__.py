"""Contact of a rigid instrument with the tissue: node contact, edge contact, friction, cutting.

* :class:`InstrumentContact`: the solver hook binding an instrument, its motion and the
  contact settings to a model (``_instrument_contact``); :class:`ContactSettings` its table
  (``_settings``);
* node contact: ``eval_contact`` (the kernel; ``_node``), ``nodal_contact_areas``,
  ``stable_penalty_fraction``;
* edge contact of a trephine's circular edge: the face lists (``_edge_faces``), the law
  (``_edge_law``) and :class:`EdgeContact`, its memory across steps (``_edge``);
* friction: :class:`Friction`, ``needle_friction_force`` (``_friction``);
* the cutting rule of the edge: the ring's averaged line load against the cutting
  toughness (``_cutting``).

Theory, choices and verification: ``docs/contact.md``.
"""

from corneasim.contact._edge import EdgeContact
from corneasim.contact._friction import Friction, FrictionValidityWarning, needle_friction_force
from corneasim.contact._instrument_contact import InstrumentContact, nodal_contact_areas, stable_penalty_fraction
from corneasim.contact._node import OUTPUT_NAMES, eval_contact
from corneasim.contact._settings import ContactSettings

__all__ = [
    "ContactSettings", "EdgeContact", "Friction", "FrictionValidityWarning", "InstrumentContact", "OUTPUT_NAMES",
    "eval_contact", "nodal_contact_areas", "needle_friction_force", "stable_penalty_fraction",
]
