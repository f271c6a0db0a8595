"""Experimental datasets from the papers, shipped as CSV package data.

:func:`read_table` reads any numeric CSV table with a header row (the format of
the package data and of user data files).
"""

from corneasim.data._csv import read_table

__all__ = ["read_table"]
