"""The N-link pendulum chain with sympy.physics.mechanics (the alternative side).

Same system as :mod:`pendulum_chain`: point masses m_i, massless rods l_i,
absolute angles th_i from the downward vertical, gravity g.  Derived with
``LagrangesMethod`` or ``KanesMethod`` and linearized about th = 0, th' = 0
with sympy's ``Linearizer``; the linearized form
``M_lin [q', u']' = A_lin [q, u]`` is cut into the mass matrix M (lower right
block of M_lin) and the stiffness matrix K = -(lower left block of A_lin).

Symbols are real and named like resonant's parameter symbols (``m1``,
``l1``, ``g``), so both sides can be compared entry by entry.

Examples
--------
>>> M, K = sympy_chain_matrices(1, "lagrange")
>>> M, K
(Matrix([[l1**2*m1]]), Matrix([[g*l1*m1]]))
"""

from __future__ import annotations

import sympy
from sympy.physics import mechanics as me


def sympy_chain_matrices(n: int, method: str = "lagrange"
                         ) -> tuple[sympy.Matrix, sympy.Matrix]:
    """Derive and linearize the n-link chain with sympy; return (M, K).

    ``method`` is ``"lagrange"`` (LagrangesMethod + linearize) or ``"kane"``
    (KanesMethod + linearize).
    """
    if method not in ("lagrange", "kane"):
        raise ValueError(f"unknown method {method!r}; use 'lagrange' or 'kane'")
    q = [me.dynamicsymbols(f"th{i}") for i in range(1, n + 1)]
    qd = [qi.diff(me.dynamicsymbols._t) for qi in q]
    u = [me.dynamicsymbols(f"u{i}") for i in range(1, n + 1)]
    m = [sympy.Symbol(f"m{i}", real=True) for i in range(1, n + 1)]
    length = [sympy.Symbol(f"l{i}", real=True) for i in range(1, n + 1)]
    g = sympy.Symbol("g", real=True)
    frame = me.ReferenceFrame("N")
    origin = me.Point("O")
    origin.set_vel(frame, 0)
    point = origin
    particles, forces = [], []
    y = sympy.Integer(0)
    for i in range(n):
        point = point.locatenew(f"P{i + 1}", length[i] * sympy.sin(q[i]) * frame.x
                                - length[i] * sympy.cos(q[i]) * frame.y)
        y = y - length[i] * sympy.cos(q[i])
        particle = me.Particle(f"pa{i + 1}", point, m[i])
        if method == "kane":
            # Kane's method works with the generalized speeds u_i = th_i'.
            point.set_vel(frame, point.pos_from(origin).dt(frame).subs(dict(zip(qd, u))))
            forces.append((point, -m[i] * g * frame.y))
        else:
            particle.potential_energy = m[i] * g * y
        particles.append(particle)
    if method == "lagrange":
        system = me.LagrangesMethod(me.Lagrangian(frame, *particles), q)
        system.form_lagranges_equations()
        lin = system.linearize(q_ind=q, qd_ind=qd, A_and_B=False,
                               op_point={**{qi: 0 for qi in q}, **{v: 0 for v in qd}})
    else:
        system = me.KanesMethod(frame, q_ind=q, u_ind=u,
                                kd_eqs=[a - b for a, b in zip(qd, u)])
        system.kanes_equations(particles, forces)
        lin = system.linearize(A_and_B=False,
                               op_point={**{qi: 0 for qi in q}, **{v: 0 for v in u}})
    M_lin, A_lin = lin[0], lin[1]
    # Kane's dynamical equations are Fr + Fr* = 0 with Fr* = -M u' - ..., so
    # their rows carry the opposite sign of Lagrange's M q'' + ... = 0.
    sign = 1 if method == "lagrange" else -1
    return sign * sympy.Matrix(M_lin[n:, n:]), -sign * sympy.Matrix(A_lin[n:, :n])
