"""Experimental features: not used by the built-in scenarios, kept for work that builds on them.

* :mod:`corneasim.experimental.split`: a mesh split along a surface (node copies);
* :mod:`corneasim.experimental.cohesive`: cohesive ties holding the split surface together
  until a cut opens it (a traction-separation law);
* :mod:`corneasim.experimental.cohesive_cut`: the scenario's ``[cohesive_cut]`` table and
  the cornea split along the trephine's cylinder.

Their tests are marked ``slow`` and left out of the default test run (``pytest -m slow``
runs them). Interfaces here may change without notice.
"""
