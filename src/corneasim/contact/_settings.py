"""Contact settings of an instrument: penalty, damping, friction, edge contact and cutting (validated, with units).

TOML example (the trephination paper's trephine)::

    [instrument.contact]
    penalty_fraction = 0.3
    friction = { law = "coulomb", coefficient = 0.1 }
    edge_contact = true
    cutting_toughness = 0.0042
"""

from __future__ import annotations

from typing import Annotated

import pydantic

from corneasim.contact._friction import Friction
from corneasim.schema import StrictModel


class ContactSettings(StrictModel):
    """Penalty contact between an instrument and the tissue.

    Attributes
    ----------
    penalty_fraction : float
        alpha in the penalty stiffness k = alpha m / dt^2 per node, dimensionless; stable
        for alpha <= 4 (1 - s^2), s the time-step safety factor (see ``docs/contact.md``).
    damping_ratio : float
        Normal dashpot as a fraction of the critical damping of each node's penalty spring,
        dimensionless (<= 0.05 keeps the strict stability bound at alpha = 0.5, s = 0.9).
    friction : Friction
        Friction law and its parameters.
    node_set : str
        Name of the mesh node set that may touch the instrument (``all`` for every node).
    edge_contact : bool
        Also test points along a trephine's circular cutting edge against the tissue's boundary
        faces, so that the edge cannot pass between nodes (3D hexahedral meshes; the node and
        the edge penalty can act on one node: stable for 2 alpha <= 4 (1 - s^2); see
        ``docs/contact.md``).
    cutting_toughness : float, optional
        With ``edge_contact``: the line load, N per mm of edge (= J/m^2 x 1e-3), at which the
        edge cuts the element it presses; that element is deleted like one whose failure
        criterion is met (a sharp blade cuts when its force per unit length reaches the
        tissue's toughness; see ``docs/contact.md``). None: the edge only presses.
    """

    penalty_fraction: Annotated[float, pydantic.Field(gt=0.0, lt=4.0)] = 0.5
    damping_ratio: Annotated[float, pydantic.Field(ge=0.0, le=1.0)] = 0.05
    friction: Friction = Friction()
    node_set: str = "all"
    edge_contact: bool = False
    cutting_toughness: Annotated[float, pydantic.Field(gt=0.0)] | None = None

    @pydantic.model_validator(mode="after")
    def _cutting_needs_the_edge(self):
        if self.cutting_toughness is not None and not self.edge_contact:
            raise ValueError("cutting_toughness needs edge_contact = true")
        return self
