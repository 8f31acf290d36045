#!/usr/bin/env python3
"""Derives the 12-point symmetric quadrature rule of degree 6 on the triangle that the Loop
elements use on regular cells (fem/src/loop_basis.cpp, reference_rule), so that its constants
can be checked or recomputed: python3 scripts/triangle_rule.py

The rule has two orbits of 3 points, barycentric (a, a, 1 - 2a), and one orbit of 6 points,
(a, b, 1 - a - b), with one weight per orbit: 7 unknowns. A rule with the triangle's symmetry
integrates every polynomial of degree <= 6 exactly when it integrates the 7 symmetric ones
(products of e2 = l1 l2 + l2 l3 + l3 l1 and e3 = l1 l2 l3 of degree <= 6, since e1 = 1). Newton's
method with a difference Jacobian, in 40-digit decimal arithmetic, from a rough start.
Weights are for the parameter triangle {s, t >= 0, s + t <= 1}, whose area is 1/2.
"""
import itertools
from decimal import Decimal, getcontext
from fractions import Fraction
from math import factorial

getcontext().prec = 40


def exact(i, j, k):
    """The integral of l1^i l2^j l3^k over the parameter triangle."""
    return Fraction(factorial(i) * factorial(j) * factorial(k), factorial(i + j + k + 2))


# The symmetric polynomials as sums of a monomial's distinct permutations: 1, e2, e3, e2^2 - 2 e3,
# e2 e3, e3^2 and one with e2^3: independent modulo e1 = 1.
EXPONENTS = [(0, 0, 0), (1, 1, 0), (1, 1, 1), (2, 2, 0), (2, 2, 1), (2, 2, 2), (3, 3, 0)]


def points(x):
    a1, w1, a2, w2, a3, b3, w3 = x
    out = []
    for a, w in ((a1, w1), (a2, w2)):
        c = 1 - 2 * a
        out += [((a, a, c), w), ((a, c, a), w), ((c, a, a), w)]
    out += [(p, w3) for p in itertools.permutations((a3, b3, 1 - a3 - b3))]
    return out


def residuals(x):
    out = []
    for m in EXPONENTS:
        forms = set(itertools.permutations(m))
        rule = sum(w * sum(l[0] ** f[0] * l[1] ** f[1] * l[2] ** f[2] for f in forms) for l, w in points(x))
        value = sum(exact(*f) for f in forms)
        out.append(rule - Decimal(value.numerator) / Decimal(value.denominator))
    return out


def solve(matrix, rhs):
    n = len(rhs)
    rows = [matrix[i][:] + [rhs[i]] for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(rows[r][c]))
        rows[c], rows[p] = rows[p], rows[c]
        for r in range(n):
            if r != c:
                f = rows[r][c] / rows[c][c]
                rows[r] = [a - f * b for a, b in zip(rows[r], rows[c])]
    return [rows[i][n] / rows[i][i] for i in range(n)]


def main():
    x = [Decimal(v) for v in ("0.06", "0.025", "0.25", "0.06", "0.64", "0.31", "0.04")]
    h = Decimal("1e-20")
    for _ in range(30):
        f = residuals(x)
        if max(abs(v) for v in f) < Decimal("1e-35"):
            break
        columns = []
        for i in range(7):
            up, down = x[:], x[:]
            up[i] += h
            down[i] -= h
            columns.append([(a - b) / (2 * h) for a, b in zip(residuals(up), residuals(down))])
        jacobian = [list(r) for r in zip(*columns)]
        x = [a + b for a, b in zip(x, solve(jacobian, [-v for v in f]))]
    print("largest moment residual:", f"{max(abs(v) for v in residuals(x)):.1e}")
    a1, w1, a2, w2, a3, b3, w3 = x
    print("orbit (a, a, 1-2a): a =", repr(float(a1)), "weight =", repr(float(w1)))
    print("orbit (a, a, 1-2a): a =", repr(float(a2)), "weight =", repr(float(w2)))
    print("orbit (a, b, 1-a-b): a =", repr(float(a3)), "b =", repr(float(b3)), "weight =", repr(float(w3)))


if __name__ == "__main__":
    main()
