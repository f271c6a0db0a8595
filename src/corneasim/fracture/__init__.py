"""Separation of tissue along a known path: a strength and a toughness.

* :mod:`corneasim.fracture._law`: the traction-separation law (strength sigma_c, toughness G_c);
* :mod:`corneasim.fracture._split`: a mesh split along a surface (node copies);
* :mod:`corneasim.fracture._ties`: cohesive ties holding the split surface together until a
  cut opens it;
* :mod:`corneasim.fracture._cohesive_cut`: the scenario's ``[cohesive_cut]`` table and the
  cornea split along the trephine's cylinder;
* :mod:`corneasim.fracture._radial_cracks`: smeared radial cracks of the needle's path (the
  local law and the kernel pass of the cut band's elements);
* :mod:`corneasim.fracture._cut_band`: the cut band of an axisymmetric model (its elements and
  its axis nodes);
* :mod:`corneasim.fracture._radial_cut`: the scenario's ``[cut]`` table.

The ties and the cohesive cut are not used by the built-in scenarios; their tests are marked
``slow`` and left out of the default test run (``pytest -m slow`` runs them).
"""

from corneasim.fracture._law import dissipated_density, envelope_traction
from corneasim.fracture._ties import CohesiveTies, tie_areas
from corneasim.fracture._cohesive_cut import CohesiveCut, cut_radius, make_ties, split_cornea
from corneasim.fracture._split import split_nodes
from corneasim.fracture._cut_band import CutAxis, RadialCracks, attach_radial_cracks, band_elements
from corneasim.fracture._radial_cut import CutBlock, RadialCut, make_radial_cut

__all__ = ["CohesiveCut", "CohesiveTies", "CutAxis", "RadialCracks", "attach_radial_cracks", "band_elements",
           "CutBlock", "RadialCut", "make_radial_cut", "cut_radius", "dissipated_density", "envelope_traction",
           "make_ties", "split_cornea", "split_nodes", "tie_areas"]
