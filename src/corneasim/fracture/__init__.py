"""Separation of tissue along a known path: a strength and a toughness.

* :mod:`corneasim.fracture._law`: the traction-separation law (strength sigma_c, toughness G_c);
* :mod:`corneasim.fracture._split`: a mesh split along a surface (node copies);
* :mod:`corneasim.fracture._ties`: cohesive ties holding the split surface together until a
  cut opens it;
* :mod:`corneasim.fracture._cohesive_cut`: the scenario's ``[cohesive_cut]`` table and the
  cornea split along the trephine's cylinder.

The ties and the cohesive cut are not used by the built-in scenarios; their tests are marked
``slow`` and left out of the default test run (``pytest -m slow`` runs them).
"""

from corneasim.fracture._law import dissipated_density, envelope_traction
from corneasim.fracture._ties import CohesiveTies, tie_areas
from corneasim.fracture._cohesive_cut import CohesiveCut, cut_radius, make_ties, split_cornea
from corneasim.fracture._split import split_nodes

__all__ = ["CohesiveCut", "CohesiveTies", "cut_radius", "dissipated_density", "envelope_traction",
           "make_ties", "split_cornea", "split_nodes", "tie_areas"]
