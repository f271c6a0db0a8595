"""corneasim: explicit finite-element simulation of instruments cutting the cornea.

Units everywhere: length mm, time s, force N, stress MPa, density tonne/mm^3,
energy mJ (N*mm).
"""

__version__ = "0.1.0"
