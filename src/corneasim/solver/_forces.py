"""The forces of a state that the model alone determines: internal (element) forces and pressures.

One call for what every force evaluation of the time loop needs, at the start of a run
(:func:`~corneasim.solver.new_state`) and in each step (:func:`~corneasim.solver.advance`):
the element kernels advance the history by ``dt`` and give f_int and the failure ratios; the
follower pressures (``_pressure``) overwrite f_ext, to which the hooks then add their forces.
A model with a cut band (``Model.radial_cracks``) evaluates the band's elements in a pass of
their own after the element kernels, which skip them (``fracture._cut_band``).
"""

from __future__ import annotations

from corneasim.solver import elements as element_kernels
from corneasim.solver._pressure import eval_pressure_forces


def eval_forces(model, state, dt: float, time: float, relaxed: bool = False) -> None:
    """f_int (N), failure ratios and energy rates of ``state`` with the element history advanced by
    ``dt`` (s; ``relaxed``: Prony terms fully relaxed), then the pressures at ``time`` (s) into
    ``state.f_ext`` (N), both at the displacement ``state.u``."""
    cracks = model.radial_cracks
    alive = state.alive if cracks is None else cracks.kernel_alive(state.alive)
    element_kernels.eval_internal_forces(state.elements, state.u, dt, alive, state.history, state.f_int,
                                         state.failure_ratio, state.energy_rates, relaxed)
    if cracks is not None:
        cracks.internal_forces(state, dt, relaxed)
    eval_pressure_forces(model.mesh.points, state.u, model.pressure_face_nodes, model.pressure_face_element,
                         model.pressure_value, model.pressure_amplitude, state.pressure_amplitude_table,
                         state.alive, time, state.f_ext)
