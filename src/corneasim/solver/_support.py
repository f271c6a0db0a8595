"""Elastic support: a node set held by linear springs in one direction.

A support stands for what holds a specimen without fixing it, e.g. an eye in a holder that
gives way when an instrument pushes on it. Every node of the set carries a spring to ground
of stiffness k_i = K / n in one component c, so that a rigid translation u of the set is
resisted by the total stiffness K:

.. math::

    f_{i,c} = -\\frac{K}{n}\\, u_{i,c}, \\qquad \\sum_i f_{i,c} = -K\\,u \\text{ for } u_{i,c} = u.

A support can hold its set while the loads of a preload settle and take the instrument's
load only afterwards, as a specimen mounted at its pressure: until the release time its
springs have the stiffness k_h,i = ``HOLD_STIFFNESS`` m_i / Δt² (as stiff as the step
allows: the set barely moves), and from then on

.. math::

    f_{i,c} = f^0_{i,c} - \\frac{K}{n}\\,(u_{i,c} - u^0_{i,c}),

with u⁰ and f⁰ = -k_h,i u⁰ each node's displacement and spring force at the release: the
equilibrium reached in the preload is kept, and only what comes after moves the set. A
preload that has not settled leaves its inertial share in f⁰ too (0.21 N on the half eye of
the short trephine test run, whose preload is 1 s at a 1e-3 s target step; at the end of the
built-in coarse trephine's preload its springs carry 1.6e-8 N): the runner warns about such
a preload (``run.preload`` in the summary).

A dashpot beside each spring, c_i = c / n, damps the translation of the whole model on the
support: c = 2 ζ sqrt(K M) with M the model's (mass-scaled) mass gives that mode the
damping ratio ζ. It matters in a mass-scaled model, whose translation on a soft support is
a slow artificial oscillation (0.1 N/mm under 0.1 t: a period of 6 s), which the solver's
mass-proportional damping leaves free (``_integrate``); the real body's is fast and
quasi-static. Its drag on a steady descent at speed ẇ is c ẇ.

The springs act as an external-force hook of the time loop (``solver._run``): their work
enters the external work of the energy balance (the energy they store is the negative of
that work). Their stiffness adds to the nodes' own; the step stays stable while
k_i Δt² / m_i stays far below 4 (central differences on one mass and spring: ω Δt < 2),
which :func:`check_support_stability` asks with a margin.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from corneasim.errors import InputError

STABILITY_MARGIN = 0.1
"""Largest k_i Δt² / m_i a support may add at a node (the bound is 4; the element stiffness
already uses most of it)."""
HOLD_STIFFNESS = 0.05
"""k_h,i Δt² / m_i of the springs that hold a set until its release (half the margin)."""


@njit(cache=True)
def add_spring_forces(u, v, nodes, component, k, dashpot, u0, f0, f_ext):
    """f_ext[i, c] += f0_j - k_j (u[i, c] - u0_j) - c v[i, c] for the nodes i = nodes[j] of the
    set; return the sum of those forces (N) and the mean u[i, c] of the set (mm).

    Parameters
    ----------
    u, v : ndarray (n_nodes, dim) float64
        Displacement (mm) and velocity (mm/s).
    nodes : ndarray (n,) int64
        The supported nodes.
    component : int
        Index of the supported component.
    k : ndarray (n,) float64
        Stiffness of each node's spring, N/mm.
    dashpot : float
        Each node's dashpot, N s/mm.
    u0, f0 : ndarray (n,) float64
        Displacement (mm) and force (N) of each node's spring at its release (zeros before).
    f_ext : ndarray (n_nodes, dim) float64
        In/out, N.
    """
    total = 0.0
    displacement = 0.0
    for j in range(nodes.size):
        i = nodes[j]
        force = f0[j] - k[j] * (u[i, component] - u0[j]) - dashpot * v[i, component]
        f_ext[i, component] += force
        total += force
        displacement += u[i, component]
    return total, displacement / nodes.size


class ElasticSupport:
    """Springs to ground on ``nodes`` in ``component``, total stiffness ``stiffness`` (N/mm).

    An external-force hook (``solver._run``): its history columns are
    ``support_<node_set>_<c>_N`` (the springs' force on the model, N) and
    ``support_<node_set>_<c>_mm`` (the set's mean displacement in c, mm).
    Call :meth:`hold` to hold the set until a release time.

    Parameters
    ----------
    node_set : str
        Name of the node set (for the columns and messages).
    nodes : ndarray (n,) int
        Its nodes.
    component : int
        Index of the supported component (0 = x or r, 1 = y or z, 2 = z).
    component_name : str
        Its name (``x``, ``y``, ``z``, ``r``).
    stiffness : float
        K, N/mm, shared equally by the nodes.
    dashpot : float
        c, N s/mm, shared equally by the nodes (:func:`critical_dashpot`).
    """

    def __init__(self, node_set: str, nodes, component: int, component_name: str, stiffness: float,
                 dashpot: float = 0.0):
        self.nodes = np.asarray(nodes, dtype=np.int64)
        if self.nodes.size == 0:
            raise InputError(f"supports: node set '{node_set}' is empty")
        self.name = f"support_{node_set}_{component_name}"
        self.component = int(component)
        self.stiffness = float(stiffness)
        self.node_stiffness = np.full(self.nodes.size, self.stiffness / self.nodes.size)
        self.node_dashpot = float(dashpot) / self.nodes.size
        self.hold_stiffness = np.zeros(self.nodes.size)
        self.release_time = -np.inf
        self.released = np.ones(1, dtype=np.uint8)
        self.u0 = np.zeros(self.nodes.size)
        self.f0 = np.zeros(self.nodes.size)
        self.force = 0.0
        self.mean_displacement = 0.0

    def hold(self, release_time: float, node_mass: np.ndarray, time_step: float) -> None:
        """Hold the set with springs of k_h,i = ``HOLD_STIFFNESS`` m_i / Δt² until
        ``release_time`` (s); ``node_mass`` (n_nodes,) tonne, ``time_step`` s."""
        self.hold_stiffness = HOLD_STIFFNESS * node_mass[self.nodes] / time_step**2
        self.release_time = float(release_time)
        self.released[0] = 0

    def add_forces(self, model, state, time: float, time_step: float, f_ext: np.ndarray) -> None:
        """Add the spring forces (N) at the displacement ``state.u`` to ``f_ext``."""
        if not self.released[0] and time > self.release_time:
            self.u0[:] = state.u[self.nodes, self.component]
            self.f0[:] = -self.hold_stiffness * self.u0
            self.released[0] = 1
        k = self.node_stiffness if self.released[0] else self.hold_stiffness
        self.force, self.mean_displacement = add_spring_forces(
            state.u, state.v, self.nodes, self.component, k, self.node_dashpot, self.u0, self.f0, f_ext)

    def checkpoint(self) -> dict[str, np.ndarray]:
        """Whether the set was released, and its springs' displacement and force then."""
        return {"released": self.released.copy(), "u0": self.u0.copy(), "f0": self.f0.copy()}

    def restore(self, arrays: dict[str, np.ndarray]) -> None:
        """Take back what :meth:`checkpoint` saved."""
        self.released[:] = arrays["released"]
        self.u0[:] = arrays["u0"]
        self.f0[:] = arrays["f0"]

    def outputs(self) -> dict[str, float]:
        """The springs' total force on the model (N) and the set's mean displacement (mm)."""
        return {f"{self.name}_N": self.force, f"{self.name}_mm": self.mean_displacement}


def critical_dashpot(damping_ratio: float, stiffness: float, mass: float) -> float:
    """c = 2 ζ sqrt(K M), N s/mm: the dashpot that gives a mass M (tonne) on a spring K (N/mm)
    the damping ratio ζ (dimensionless)."""
    return 2.0 * damping_ratio * float(np.sqrt(stiffness * mass))


def check_support_stability(support: ElasticSupport, node_mass: np.ndarray, time_step: float,
                            where: str) -> None:
    """Raise InputError when a spring or a dashpot would take the step near its stability limit.

    Each node's spring must keep k_i Δt² / m_i and its dashpot c_i Δt / m_i below
    :data:`STABILITY_MARGIN`. ``node_mass`` (n_nodes,) tonne; ``time_step`` the run's step
    (or target), s; ``where`` names the support (``supports[k]``) in the message.
    """
    mass = float(np.min(node_mass[support.nodes]))
    spring = support.stiffness / support.nodes.size * time_step**2
    if not spring < STABILITY_MARGIN * mass:
        limit = STABILITY_MARGIN * mass / time_step**2 * support.nodes.size
        raise InputError(f"{where}.stiffness: {support.stiffness:g} N/mm over {support.nodes.size} nodes is too "
                         f"stiff for the time step {time_step:.3g} s (at most {limit:.3g} N/mm on this mesh)")
    if not support.node_dashpot * time_step < STABILITY_MARGIN * mass:
        raise InputError(f"{where}.damping_ratio: the dashpot is too strong for the time step {time_step:.3g} s")
