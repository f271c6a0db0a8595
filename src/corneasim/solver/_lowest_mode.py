"""The lowest natural period of a model, for choosing the ramp of a quasi-static run.

The fundamental mode solves K phi = omega^2 M phi on the free dofs (the constrained and
prescribed ones held), with M the lumped (mass-scaled) masses and K the tangent stiffness
at the reference state. K is never assembled: K x is the directional derivative of the
internal forces, (f_int(epsilon x) - f_int(0)) / epsilon at a displacement epsilon x small
enough that the response is linear (epsilon |x| = 1e-7 of the model's size), evaluated by the
element kernels with zero time step (the instantaneous elastic response with the hourglass
stiffness; no bulk viscosity). The smallest eigenpair comes from LOBPCG (Knyazev 2001,
SIAM J. Sci. Comput. 23:517) preconditioned by the inverse of a diagonal estimate of K
(m_i (2 / dt_i)^2, the nodal mass times the square of the highest frequency of its elements).
The period is T_1 = 2 pi / omega_1 (s).
"""

from __future__ import annotations

import warnings

import numpy as np

from corneasim.solver import elements as element_kernels

DENSE_LIMIT = 300
"""Up to this many free dofs the eigenproblem is solved densely (LOBPCG needs more than five
times its block size)."""

RESTART_ITERATIONS = 20
"""LOBPCG iterations per round of :func:`lowest_period`."""

PROBE_STRAIN = 1e-7
"""Size of the probing displacement relative to the model's size (linear response)."""


def _internal_force(model, u: np.ndarray, history: np.ndarray) -> np.ndarray:
    f_int = np.zeros((model.n_nodes, model.dim))
    alive = np.ones(model.n_elements, np.uint8)
    element_kernels.eval_internal_forces(model.elements, u, 0.0, alive, history.copy(), f_int,
                                         np.zeros(model.n_elements), np.zeros(3))
    return f_int.ravel()


def lowest_period(model, tolerance: float = 1e-4, max_restarts: int = 40) -> float:
    """The lowest natural period T_1 of ``model`` (s): module notes.

    LOBPCG runs in rounds of ``RESTART_ITERATIONS`` iterations until omega_1^2 changes by less
    than ``tolerance`` (relative) from one round to the next (at most ``max_restarts`` rounds).

    Raises ``ValueError`` for a model without free dofs.
    """
    from scipy.linalg import eigh  # deferred: only the quasi-static recipe needs the period
    from scipy.sparse.linalg import LinearOperator, lobpcg

    free = np.flatnonzero(model.dof_constrained.ravel() == 0)
    if free.size == 0:
        raise ValueError("the model has no free degree of freedom")
    points = model.mesh.points
    size = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
    history = element_kernels.new_history(model.elements)
    base = _internal_force(model, np.zeros((model.n_nodes, model.dim)), history)
    mass = model.dof_mass[free]

    def stiffness(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x).reshape(free.size, -1)
        out = np.empty_like(x)
        for k in range(x.shape[1]):
            scale = PROBE_STRAIN * size / max(float(np.abs(x[:, k]).max()), 1e-300)
            u = np.zeros(model.n_nodes * model.dim)
            u[free] = scale * x[:, k]
            out[:, k] = (_internal_force(model, u.reshape(model.n_nodes, model.dim), history) - base)[free] / scale
        return out

    node_step = np.full(model.n_nodes, np.inf)
    steps = model.element_time_step * np.sqrt(model.density_scale)
    np.minimum.at(node_step, model.mesh.cells, steps[:, None])
    diagonal = mass * (2.0 / np.repeat(node_step, model.dim)[free]) ** 2
    n = free.size
    operator = LinearOperator((n, n), matvec=stiffness, matmat=stiffness, dtype=float)
    mass_operator = LinearOperator((n, n), matvec=lambda x: mass * np.ravel(x),
                                   matmat=lambda x: mass[:, None] * x, dtype=float)
    preconditioner = LinearOperator((n, n), matvec=lambda x: np.ravel(x) / diagonal,
                                    matmat=lambda x: x / diagonal[:, None], dtype=float)
    coordinates = points[np.arange(model.n_nodes).repeat(model.dim)][free]
    centred = (coordinates - coordinates.mean(axis=0)) / size
    candidates = np.column_stack([np.ones(n), *centred.T, np.sin(np.pi * centred[:, -1]),
                                  np.sin(np.pi * centred[:, 0])])
    q, r = np.linalg.qr(candidates)  # smooth start vectors; the dependent ones (flat meshes) dropped
    guess = q[:, np.abs(np.diag(r)) > 1e-8 * np.abs(np.diag(r)).max()]
    if n <= DENSE_LIMIT:  # small models: the dense generalised eigenproblem, exactly
        dense = stiffness(np.eye(n))
        value = float(eigh(0.5 * (dense + dense.T), np.diag(mass), eigvals_only=True, subset_by_index=(0, 0))[0])
        return 2.0 * np.pi / float(np.sqrt(max(value, 1e-300)))
    previous = np.inf
    with warnings.catch_warnings():  # the residual norms are dimensional: convergence is judged on omega^2
        warnings.simplefilter("ignore")
        for _ in range(max_restarts):
            values, guess = lobpcg(operator, guess, B=mass_operator, M=preconditioner, largest=False,
                                   tol=1e-300, maxiter=RESTART_ITERATIONS)
            value = float(np.min(values))
            if abs(value - previous) <= tolerance * abs(value):
                break
            previous = value
    omega = float(np.sqrt(max(value, 1e-300)))
    return 2.0 * np.pi / omega
