"""Experimental datasets from the papers, shipped as CSV package data.

:func:`list_datasets` and :func:`load_dataset` give the papers' tables (needle
insertion force, trephination force, their Gaussian fits, the porcine eye
geometry) with units and sources; :func:`read_table` reads any numeric CSV table
with a header row (the format of the package data and of user data files).
See ``docs/data.md``.
"""

from corneasim.data._csv import read_table
from corneasim.data._registry import (
    Dataset,
    column_unit,
    list_datasets,
    load_dataset,
    load_dataset_file,
)

__all__ = ["Dataset", "column_unit", "list_datasets", "load_dataset", "load_dataset_file", "read_table"]
