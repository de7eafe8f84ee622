#!/usr/bin/env python3
"""The SymPy peer of the benchmarks: Hamilton's equations of the planar n-link pendulum and
their Jacobian, derived the way a SymPy user would, printed as C99 for the same interface as
npend's generated kernels.

The recipe, step by step as in SymPy's documentation: the kinematics x_k = Σ l_i sin φ_i,
y_k = Σ l_i cos φ_i (y down); T = Σ m_k/2 |ṙ_k|² and V = −g Σ m_k y_k; the mass matrix
A = hessian(T, φ̇), each entry trigsimp'ed (to μ l_i l_j cos(φ_i − φ_j)); φ̇ = A⁻¹p
by LUsolve; H = ½ pᵀA⁻¹p + V; Hamilton's equations
f = (∂H/∂p, −∂H/∂φ); the Jacobian f.jacobian(x); cse; C99 printing. Without the trigsimp
of A the derivation takes 3× longer (145 s instead of 45 s at n = 4 here) and the code is
bigger; simplify() of the equations themselves does not finish for n ≥ 3.

Writes OUT/sympy_chain_<n>.c with
    void npend_sympy_rhs_<n>(const double* x, const double* params, double* dxdt);
    void npend_sympy_jacobian_<n>(const double* x, const double* params, double* jac);
(x = [φ_1..φ_n, p_1..p_n], params = [m_1..m_n, l_1..l_n, g] — npend::chain_layout in runtime/include/npend/chain_kernels.hpp; the tests feed both this peer and the generated kernels chain_parameters::packed(), so a different layout fails them — jac row-major 2n × 2n) and
OUT/sympy_chain_<n>.json with the seconds each step took and the size of the output.
"""
import argparse
import json
import pathlib
import sys
import time

import sympy as sp
from sympy.printing.c import C99CodePrinter


def derive(n):
    """Hamilton's equations f and their Jacobian J for n links, as SymPy matrices."""
    phi = sp.symbols(f"phi1:{n + 1}", real=True)
    dphi = sp.symbols(f"dphi1:{n + 1}", real=True)
    p = sp.symbols(f"p1:{n + 1}", real=True)
    m = sp.symbols(f"m1:{n + 1}", positive=True)
    l = sp.symbols(f"l1:{n + 1}", positive=True)
    g = sp.Symbol("g", positive=True)

    x_pos = [sum(l[i] * sp.sin(phi[i]) for i in range(k + 1)) for k in range(n)]
    y_pos = [sum(l[i] * sp.cos(phi[i]) for i in range(k + 1)) for k in range(n)]

    def rate(expr):
        return sum(sp.diff(expr, phi[i]) * dphi[i] for i in range(n))

    T = sum(m[k] / 2 * (rate(x_pos[k]) ** 2 + rate(y_pos[k]) ** 2) for k in range(n))
    V = -g * sum(m[k] * y_pos[k] for k in range(n))

    A = sp.hessian(T, dphi).applyfunc(sp.trigsimp)
    p_vec = sp.Matrix(p)
    velocities = A.LUsolve(p_vec)
    H = (p_vec.T * velocities)[0, 0] / 2 + V

    f = sp.Matrix([sp.diff(H, pk) for pk in p] + [-sp.diff(H, qk) for qk in phi])
    state = list(phi) + list(p)
    J = f.jacobian(state)
    return f, J, state, list(m) + list(l) + [g]


def count_trig(exprs):
    return sum(1 for e in exprs for a in sp.preorder_traversal(e) if isinstance(a, (sp.sin, sp.cos)))


def c_function(name, outputs, out_name, state, params, printer):
    """One C function: unpack the inputs, cse, one assignment per output entry."""
    started = time.perf_counter()
    replacements, reduced = sp.cse(outputs)
    cse_seconds = time.perf_counter() - started

    started = time.perf_counter()
    lines = [f"void {name}(const double* x, const double* params, double* {out_name}) {{"]
    lines += [f"  const double {s} = x[{i}];" for i, s in enumerate(state)]
    lines += [f"  const double {s} = params[{i}];" for i, s in enumerate(params)]
    lines += [f"  const double {s} = {printer.doprint(e)};" for s, e in replacements]
    lines += [f"  {out_name}[{i}] = {printer.doprint(e)};" for i, e in enumerate(reduced)]
    lines.append("}")
    print_seconds = time.perf_counter() - started

    exprs = [e for _, e in replacements] + list(reduced)
    stats = {"ops": int(sum(sp.count_ops(e) for e in exprs)), "trig": count_trig(exprs)}
    return "\n".join(lines) + "\n", cse_seconds, print_seconds, stats


def write_chain(n, out_dir):
    started = time.perf_counter()
    f, J, state, params = derive(n)
    derive_seconds = time.perf_counter() - started

    printer = C99CodePrinter()
    rhs_code, rhs_cse, rhs_print, rhs_stats = c_function(
        f"npend_sympy_rhs_{n}", list(f), "dxdt", state, params, printer)
    jac_code, jac_cse, jac_print, jac_stats = c_function(
        f"npend_sympy_jacobian_{n}", list(J), "jac", state, params, printer)

    source = (f"/* Written by bench/sympy_peer.py --links {n}: the SymPy peer of the npend "
              "benchmarks. Do not edit. */\n#include <math.h>\n\n" + rhs_code + "\n" + jac_code)
    (out_dir / f"sympy_chain_{n}.c").write_text(source)
    stats = {
        "n": n,
        "sympy": sp.__version__,
        "derive_seconds": derive_seconds,
        "cse_seconds": rhs_cse + jac_cse,
        "print_seconds": rhs_print + jac_print,
        "seconds": derive_seconds + rhs_cse + jac_cse + rhs_print + jac_print,
        "bytes": len(source.encode()),
        "rhs_ops": rhs_stats["ops"],
        "jacobian_ops": jac_stats["ops"],
        "rhs_trig": rhs_stats["trig"],
    }
    (out_dir / f"sympy_chain_{n}.json").write_text(json.dumps(stats, indent=1) + "\n")
    return stats


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--links", required=True,
                        help="link counts, comma-separated (SymPy needs ~1 min at 4 links)")
    parser.add_argument("--out", required=True, type=pathlib.Path, help="output directory")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for n in (int(v) for v in args.links.split(",")):
        stats = write_chain(n, args.out)
        print(f"sympy_peer: {n} links in {stats['seconds']:.1f} s "
              f"(derive {stats['derive_seconds']:.1f}, cse {stats['cse_seconds']:.1f}), "
              f"{stats['bytes']} bytes", file=sys.stderr)


if __name__ == "__main__":
    main()
