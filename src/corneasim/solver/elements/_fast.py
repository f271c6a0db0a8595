"""Block-major packing of an ElementSet for the fast kernels, and their dispatch.

Every per-element array becomes ``(n_blocks, n_fields, block_size)`` so that one block's
data streams contiguously; the last block is padded with copies of the last element
(masked out).
"""

from __future__ import annotations

import numpy as np

from corneasim.materials.kernel import (
    M_PRONY_A, M_PRONY_B, MAX_PRONY_TERMS, P_FIBRE_K1, P_N_PRONY, packed_constants)
from corneasim.solver.elements import _fast_hex, _fast_quad
from corneasim.solver.elements._material_point import step_prony_coefficients
from corneasim.solver.elements._reduce import part_layout, sum_part_forces
from corneasim.solver.elements._schedule import kernel_threads


def _blocked(values, n_blocks, block):
    """(n_e, n_fields) -> (n_blocks, n_fields, block), padded with the last row (its nodes
    are local to the last block, which keeps the thread's node range short)."""
    n_e = values.shape[0]
    padded = np.concatenate([values, np.repeat(values[-1:], n_blocks * block - n_e, axis=0)])
    return np.ascontiguousarray(padded.reshape(n_blocks, block, -1).transpose(0, 2, 1))


def pack(elements, block):
    """Block-major arrays of ``elements`` for the fast kernels (a dict)."""
    n_e = elements.n_elements
    n_blocks = elements.n_blocks
    cells = elements.cells
    if elements.kind == "quad":
        per_element = np.concatenate([
            elements.b[:, :, 0], elements.b[:, :, 1], elements.hoop, elements.gamma[:, 0, :],
            np.stack([elements.volume, elements.hourglass_stiffness, elements.bulk_linear,
                      elements.bulk_quadratic], axis=1)], axis=1)
    else:
        per_element, cells = _fast_hex.hadamard_geometry(elements)
    blocked_cells = _blocked(cells, n_blocks, block)
    parts = part_layout(blocked_cells, elements.points.shape[0])
    block_material = np.full(n_blocks, -1, np.int64)
    for blk in range(n_blocks):
        present = np.unique(elements.element_material[blk * block:(blk + 1) * block])
        if present.size == 1:
            block_material[blk] = present[0]
    viscous = elements.material_table[elements.element_material, P_N_PRONY] > 0
    viscous_blocks = np.zeros(n_blocks, np.uint8)  # blocks with Prony terms (softening keeps them)
    np.maximum.at(viscous_blocks, np.arange(n_e) // block, viscous.astype(np.uint8))
    # the fibre frame rows: (m_r, m_z) for quads (n is the hoop direction), (m, n) for hexahedra;
    # None without fibre materials (the kernels are then compiled without the fibre term)
    frame = None
    if np.any(elements.material_table[elements.element_material, P_FIBRE_K1] > 0):
        frame = elements.fibre_frame[:, :2] if elements.kind == "quad" else elements.fibre_frame
        frame = _blocked(frame, n_blocks, block).ravel()
    return dict(
        cells=blocked_cells.astype(np.int32), **parts,
        row_forces=np.zeros(parts["n_rows"] * elements.points.shape[1]),
        part_energy=np.zeros((parts["part_block"].size - 1, 3)),
        geometry=_blocked(per_element, n_blocks, block).ravel(),
        material=packed_constants(elements.material_table),
        block_material=block_material, prony_step=None,
        element_material=_blocked(elements.element_material[:, None], n_blocks,
                                  block)[:, 0, :].copy(),
        viscous_blocks=viscous_blocks, fibre_frame=frame, scratch=None,
        block=block)


FORCE_KERNELS = (_fast_quad.quad_internal_forces, _fast_hex.hex_internal_forces)
"""The element-force kernels (the run's hot loops), for ``output.platform.compiled_in_process``."""


def internal_forces(elements, dt, u, alive, history, f_int, failure_ratio, energy_rates,
                    relaxed=False):
    """Dispatch to the fast kernel of the element kind (threads: ``_schedule.kernel_threads``);
    ``relaxed``: ``_api.eval_internal_forces``."""
    fast = elements.fast
    if (dt, relaxed) != fast["prony_step"]:
        prony_a, prony_b = step_prony_coefficients(elements.material_table, dt, relaxed)
        fast["material"][:, M_PRONY_A:M_PRONY_A + MAX_PRONY_TERMS] = prony_a
        fast["material"][:, M_PRONY_B:M_PRONY_B + MAX_PRONY_TERMS] = prony_b
        fast["prony_step"] = (dt, relaxed)  # what the Prony factors in "material" are for
    nt = kernel_threads(elements)
    if fast["scratch"] is None or fast["scratch"].shape[0] != nt:
        n_scratch = _fast_quad.N_SCRATCH if elements.kind == "quad" else _fast_hex.N_SCRATCH
        fast["scratch"] = np.zeros((nt, n_scratch * fast["block"]))
    if not history.flags.c_contiguous:
        raise ValueError("history must be the C-contiguous array from new_history")
    kernel = (_fast_quad.quad_internal_forces if elements.kind == "quad"
              else _fast_hex.hex_internal_forces)
    kernel(u, 2.0 / dt if dt > 0.0 else 0.0, alive, fast["cells"], fast["cells_target"],
           fast["geometry"], fast["material"], fast["block_material"], fast["element_material"],
           history.reshape(-1), fast["part_block"], fast["viscous_blocks"], fast["fibre_frame"],
           fast["row_forces"], fast["scratch"], fast["part_energy"], failure_ratio)
    sum_part_forces(fast["row_forces"], fast["shared_node"], fast["shared_start"],
                    fast["chunk_shared"], fast["part_energy"], f_int, energy_rates, nt)
