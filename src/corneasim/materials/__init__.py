"""Material laws: hyperelasticity, Prony viscoelasticity, failure criteria, stability, fitting."""

from corneasim.materials._kernel_form import KernelMaterial, kernel_table

__all__ = ["KernelMaterial", "kernel_table"]
