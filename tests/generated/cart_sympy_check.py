#!/usr/bin/env python3
"""The generated kernels of the chain on a cart against an independent SymPy derivation.

Derives the equations from scratch, sharing nothing with npend-gen but the parameter order of
the contract (runtime/include/npend/chain_kernels.hpp, cart_layout): the Lagrangian from the
positions of the mass points (y up here, where the generator takes y down), Rayleigh's
dissipation function and the virtual work of the force and the joint torques, then the
Legendre transform p = dL/dq' and Hamilton's equations q' = A^-1 p, p' = dL/dq + Q. Evaluated
in 40-digit arithmetic at random states, parameters and inputs and compared with the rhs the
driver (cart_rhs_driver) prints: each half of dxdt (q', p') to 1e-12 of its largest entry.

Usage: cart_sympy_check.py <cart_rhs_driver>. Exit 0 when all agree, 1 on a mismatch, 77
(skipped) without SymPy.
"""
import random
import subprocess
import sys

try:
    import sympy as sp
except ImportError:
    print("cart_sympy_check: SymPy is not installed: skipped")
    sys.exit(77)

TOLERANCE = 1e-12
DIGITS = 40


def cart_equations(n):
    """Symbols and the pieces of Hamilton's equations of n links on a cart."""
    t = sp.Symbol("t")
    x = sp.Function("x")(t)
    phi = [sp.Function(f"phi{i + 1}")(t) for i in range(n)]
    q = [x] + phi
    m = sp.symbols(f"m1:{n + 1}")
    l = sp.symbols(f"l1:{n + 1}")
    c = sp.symbols(f"c1:{n + 1}")
    J = sp.symbols(f"J1:{n + 1}")
    k = sp.symbols(f"k1:{n + 1}")
    rest = sp.symbols(f"rest1:{n + 1}")
    b = sp.symbols(f"b1:{n + 1}")
    u = sp.symbols(f"u1:{n + 1}")
    g, M, bx, F = sp.symbols("g M bx F")

    # Link k's centre of mass, c_k down link k from its upper joint; y up, pivot at (x, 0).
    T = M / 2 * sp.diff(x, t) ** 2
    V = 0
    joint_x, joint_y = x, sp.Integer(0)
    for i in range(n):
        px = joint_x + c[i] * sp.sin(phi[i])
        py = joint_y - c[i] * sp.cos(phi[i])
        T += m[i] / 2 * (sp.diff(px, t) ** 2 + sp.diff(py, t) ** 2)
        T += J[i] / 2 * sp.diff(phi[i], t) ** 2
        V += m[i] * g * py
        joint_x += l[i] * sp.sin(phi[i])
        joint_y -= l[i] * sp.cos(phi[i])
    # Joint i joins link i-1 (the cart for i = 0) to link i: theta_i = phi_i - phi_{i-1}.
    theta = [phi[0]] + [phi[i] - phi[i - 1] for i in range(1, n)]
    R = bx / 2 * sp.diff(x, t) ** 2
    work = F * x
    for i in range(n):
        V += k[i] / 2 * (theta[i] - rest[i]) ** 2
        R += b[i] / 2 * sp.diff(theta[i], t) ** 2
        work += u[i] * theta[i]

    # Plain symbols for q and q' so that partial derivatives are ordinary ones.
    qs = sp.symbols(f"q0:{n + 1}")
    vs = sp.symbols(f"v0:{n + 1}")
    to_plain = {sp.diff(qi, t): vi for qi, vi in zip(q, vs)}
    to_plain.update({qi: qsi for qi, qsi in zip(q, qs)})
    L = (T - V).subs(to_plain)
    R = R.subs(to_plain)
    work = work.subs(to_plain)
    momenta = [sp.diff(L, v) for v in vs]
    A = sp.Matrix(n + 1, n + 1, lambda i, j: sp.diff(momenta[i], vs[j]))
    rates = [sp.diff(L, qi) + sp.diff(work, qi) - sp.diff(R, vi) for qi, vi in zip(qs, vs)]
    params = list(m) + list(l) + [g] + list(c) + list(J) + list(k) + list(rest) + list(b)
    params += [M, bx]
    return {"q": qs, "v": vs, "A": A, "rates": rates, "params": params, "inputs": [F] + list(u)}


def reference_rhs(eq, params, state, inputs):
    """Hamilton's equations at one point, in DIGITS-digit arithmetic."""
    n1 = len(eq["q"])
    num = lambda v: sp.Float(repr(v), DIGITS)
    values = {s: num(v) for s, v in zip(eq["params"], params)}
    values.update({s: num(v) for s, v in zip(eq["inputs"], inputs)})
    values.update({s: num(v) for s, v in zip(eq["q"], state[:n1])})
    p = sp.Matrix([num(v) for v in state[n1:]])
    A = eq["A"].subs(values).evalf(DIGITS)
    qdot = A.LUsolve(p)
    values.update({s: qdot[i] for i, s in enumerate(eq["v"])})
    pdot = [r.subs(values).evalf(DIGITS) for r in eq["rates"]]
    return [float(v) for v in qdot] + [float(v) for v in pdot]


def random_case(rng, n, links):
    """Parameters [m, l, g, c, J, k, rest, b, M, bx], a state and inputs for n links."""
    m = [rng.uniform(0.3, 2.0) for _ in range(n)]
    l = [rng.uniform(0.4, 1.5) for _ in range(n)]
    if links == "point":  # point masses: the mass at the end of a massless rod
        c, J = list(l), [0.0] * n
    else:  # uniform rods
        c = [li / 2 for li in l]
        J = [mi * li * li / 12 for mi, li in zip(m, l)]
    k = [rng.uniform(0.0, 3.0) for _ in range(n)]
    rest = [rng.uniform(-0.5, 0.5) for _ in range(n)]
    b = [rng.uniform(0.0, 0.8) for _ in range(n)]
    params = m + l + [9.81] + c + J + k + rest + b + [rng.uniform(0.5, 3.0), rng.uniform(0.0, 1.0)]
    state = [rng.uniform(-1.0, 1.0)] + [rng.uniform(-3.1, 3.1) for _ in range(n)]
    state += [rng.uniform(-2.0, 2.0) for _ in range(n + 1)]
    inputs = [rng.uniform(-5.0, 5.0) for _ in range(n + 1)]
    return params, state, inputs


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    rng = random.Random(20261126)
    cases = []
    for n, links in ((1, "point"), (2, "point"), (1, "rod")):
        eq = cart_equations(n)
        for _ in range(4):
            params, state, inputs = random_case(rng, n, links)
            cases.append((n, links, params, state, inputs, reference_rhs(eq, params, state, inputs)))
    lines = "".join(
        " ".join([str(n)] + [repr(v) for v in params + state + inputs]) + "\n"
        for n, _, params, state, inputs, _ in cases)
    run = subprocess.run([sys.argv[1]], input=lines, capture_output=True, text=True, check=True)
    outputs = run.stdout.splitlines()
    if len(outputs) != len(cases):
        print(f"cart_sympy_check: the driver printed {len(outputs)} lines for {len(cases)} cases")
        return 1
    failures = 0
    for (n, links, _, _, _, want), line in zip(cases, outputs):
        got = [float(v) for v in line.split()]
        half = n + 1
        for name, g, w in (("dq/dt", got[:half], want[:half]), ("dp/dt", got[half:], want[half:])):
            scale = max(abs(v) for v in w)
            error = max(abs(a - b) for a, b in zip(g, w))
            ok = error <= TOLERANCE * scale
            failures += not ok
            print(f"{n} link(s), {links}: {name} max error {error:.3g} of scale {scale:.3g}"
                  f"{'' if ok else '  MISMATCH'}")
    print(f"cart_sympy_check: {len(cases)} states, {failures} mismatches")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
