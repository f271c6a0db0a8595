"""Experimental features: not used by the built-in scenarios, kept for work that builds on them.

* :mod:`corneasim.experimental._split`: a mesh split along a surface (node copies);
* :mod:`corneasim.experimental._cohesive`: cohesive ties holding the split surface together
  until a cut opens it (a traction-separation law);
* :mod:`corneasim.experimental._cohesive_cut`: the scenario's ``[cohesive_cut]`` table and
  the cornea split along the trephine's cylinder.

Their tests are marked ``slow`` and left out of the default test run (``pytest -m slow``
runs them). Interfaces here may change without notice.
"""

from corneasim.experimental._cohesive import CohesiveTies, tie_areas
from corneasim.experimental._cohesive_cut import CohesiveCut, cut_radius, make_ties, split_cornea
from corneasim.experimental._split import split_nodes

__all__ = ["CohesiveCut", "CohesiveTies", "cut_radius", "make_ties", "split_cornea", "split_nodes",
           "tie_areas"]
