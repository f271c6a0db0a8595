"""corneasim: explicit finite-element simulation of instruments cutting the cornea.

Units everywhere: length mm, time s, force N, stress MPa, density tonne/mm^3,
energy mJ (N*mm).

>>> import corneasim
>>> callable(corneasim.run_scenario)
True
"""

from corneasim.scenarios import run_scenario

__version__ = "0.1.0"
__all__ = ["run_scenario", "__version__"]
